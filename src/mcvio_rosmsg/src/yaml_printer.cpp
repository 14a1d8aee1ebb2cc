#include "mcvio/rosmsg/yaml_printer.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace mcvio::rosmsg {
namespace {

std::string scalar(const MessageValue& v) {
  if (auto b = std::get_if<bool>(&v.value)) return *b ? "true" : "false";
  if (auto i = std::get_if<std::int64_t>(&v.value)) return std::to_string(*i);
  if (auto u = std::get_if<std::uint64_t>(&v.value)) return std::to_string(*u);
  if (auto d = std::get_if<double>(&v.value)) {
    if (std::isnan(*d)) return ".nan";
    if (std::isinf(*d)) return *d > 0 ? ".inf" : "-.inf";
    // Shortest text that reads back to the same double: 0.07395907, not 0.073959070000000002.
    char buf[32];
    for (int precision = 15; precision <= 17; ++precision) {
      std::snprintf(buf, sizeof buf, "%.*g", precision, *d);
      if (std::strtod(buf, nullptr) == *d) break;
    }
    std::string s = buf;
    if (s.find_first_of(".e") == std::string::npos) s += ".0";
    return s;
  }
  const auto& s = std::get<std::string>(v.value);
  std::string out = "'";
  for (char c : s) out += (c == '\'') ? std::string("''") : std::string(1, c);
  return out + "'";
}

bool isScalar(const MessageValue& v) {
  return !std::holds_alternative<MessageValue::Fields>(v.value) &&
         !std::holds_alternative<MessageValue::Array>(v.value) &&
         !std::holds_alternative<MessageValue::Bytes>(v.value);
}

void print(const MessageValue& v, int indent, const YamlPrintOptions& opt, std::string& out);

void printListItems(const MessageValue::Array& arr, int indent, const YamlPrintOptions& opt,
                    std::string& out) {
  const std::string pad(indent, ' ');
  const std::size_t shown = opt.max_array_elements ? std::min(arr.size(), opt.max_array_elements) : arr.size();
  for (std::size_t i = 0; i < shown; ++i) {
    if (isScalar(arr[i])) {
      out += pad + "- " + scalar(arr[i]) + "\n";
    } else {
      std::string inner;
      print(arr[i], indent + 2, opt, inner);
      // Put the first key on the dash line, as YAML block sequences of mappings do.
      out += pad + "- " + inner.substr(indent + 2);
    }
  }
  if (shown < arr.size()) out += pad + "- '... (" + std::to_string(arr.size() - shown) + " more)'\n";
}

void print(const MessageValue& v, int indent, const YamlPrintOptions& opt, std::string& out) {
  const std::string pad(indent, ' ');
  for (const auto& [name, fv] : std::get<MessageValue::Fields>(v.value)) {
    if (isScalar(fv)) {
      out += pad + name + ": " + scalar(fv) + "\n";
    } else if (auto* f = std::get_if<MessageValue::Fields>(&fv.value)) {
      out += pad + name + ":" + (f->empty() ? " {}\n" : "\n");
      print(fv, indent + 2, opt, out);
    } else if (auto* b = std::get_if<MessageValue::Bytes>(&fv.value)) {
      const std::size_t shown = opt.max_array_elements ? std::min(b->size(), opt.max_array_elements) : b->size();
      out += pad + name + ":" + (b->empty() ? " []\n" : "\n");
      for (std::size_t i = 0; i < shown; ++i) out += pad + "- " + std::to_string((*b)[i]) + "\n";
      if (shown < b->size()) out += pad + "- '... (" + std::to_string(b->size() - shown) + " more)'\n";
    } else {
      const auto& arr = std::get<MessageValue::Array>(fv.value);
      out += pad + name + ":" + (arr.empty() ? " []\n" : "\n");
      printListItems(arr, indent, opt, out);
    }
  }
}

}  // namespace

std::string toYaml(const MessageValue& value, const YamlPrintOptions& options) {
  std::string out;
  print(value, 0, options, out);
  return out;
}

}  // namespace mcvio::rosmsg
