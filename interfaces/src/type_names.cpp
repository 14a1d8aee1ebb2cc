#include "mcvio/interfaces/type_names.hpp"

#include <stdexcept>

namespace mcvio::interfaces {

std::string rosToDdsTypeName(std::string_view ros_type) {
  const auto first = ros_type.find('/');
  const auto last = ros_type.rfind('/');
  if (first == std::string_view::npos || first == last || first == 0 ||
      last + 1 >= ros_type.size() || ros_type.find('/', first + 1) != last) {
    throw std::invalid_argument("type name '" + std::string(ros_type) +
                                "' is not of the form pkg/msg/Name");
  }
  std::string out(ros_type.substr(0, first));
  out += "::";
  out += ros_type.substr(first + 1, last - first - 1);
  out += "::dds_::";
  out += ros_type.substr(last + 1);
  out += '_';
  return out;
}

std::optional<std::string> ddsToRosTypeName(std::string_view dds_type) {
  constexpr std::string_view kDds = "::dds_::";
  const auto dds = dds_type.rfind(kDds);
  if (dds == std::string_view::npos || dds_type.size() < dds + kDds.size() + 2 ||
      dds_type.back() != '_') {
    return std::nullopt;
  }
  const auto ns = dds_type.substr(0, dds);  // "pkg::msg"
  const auto sep = ns.find("::");
  if (sep == std::string_view::npos || sep == 0 || ns.find("::", sep + 2) != std::string_view::npos) {
    return std::nullopt;
  }
  std::string out(ns.substr(0, sep));
  out += '/';
  out += ns.substr(sep + 2);
  out += '/';
  out += dds_type.substr(dds + kDds.size(), dds_type.size() - dds - kDds.size() - 1);
  return out;
}

}  // namespace mcvio::interfaces
