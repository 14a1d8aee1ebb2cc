#include "mcvio/interfaces/message_registry.hpp"

#include <algorithm>
#include <stdexcept>

namespace mcvio::interfaces {
namespace {

const MessageDescription kDescriptions[] = {
#include "mcvio/interfaces/message_registry_data.inc"
};

}  // namespace

const std::vector<MessageDescription>& MessageRegistry::all() {
  static const std::vector<MessageDescription> sorted = [] {
    std::vector<MessageDescription> v(std::begin(kDescriptions), std::end(kDescriptions));
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
    return v;
  }();
  return sorted;
}

const MessageDescription* MessageRegistry::find(std::string_view ros_type) {
  const auto& v = all();
  auto it = std::lower_bound(v.begin(), v.end(), ros_type,
                             [](const MessageDescription& d, std::string_view n) { return d.name < n; });
  return (it != v.end() && it->name == ros_type) ? &*it : nullptr;
}

const MessageDescription& MessageRegistry::get(std::string_view ros_type) {
  if (const auto* d = find(ros_type)) return *d;
  std::string known;
  for (const auto& d : all()) known += "\n  " + std::string(d.name);
  throw std::invalid_argument("unknown message type '" + std::string(ros_type) +
                              "'; mcvio knows:" + known);
}

}  // namespace mcvio::interfaces
