#include "yaml_section.hpp"

#include <cmath>

#include "mcvio/core/input_error.hpp"
#include "number_format.hpp"

namespace mcvio::dataset::detail {

YamlSection::YamlSection(std::string path, std::string section, YAML::Node node)
    : path_(std::move(path)), section_(std::move(section)), node_(std::move(node)) {}

YAML::Node YamlSection::require(const YAML::Node& parent, const std::string& key) const {
  const YAML::Node node = parent[key];
  if (!node) throw InputError(path_ + ": " + prefix() + "missing key '" + key + "'");
  return node;
}

void YamlSection::fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
  const YAML::Mark mark = node.Mark();
  const std::string line = mark.line >= 0 ? ":" + std::to_string(mark.line + 1) : "";
  throw InputError(path_ + line + ": " + prefix() + "key '" + key + "' " + what);
}

double YamlSection::number(const YAML::Node& node, const std::string& key) const {
  double value = 0.0;
  if (!node.IsScalar()) fail(node, key, "must be a number");
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    fail(node, key, "must be a number, got '" + node.Scalar() + "'");
  }
  if (!std::isfinite(value)) fail(node, key, "must be finite");
  return value;
}

double YamlSection::positive(const std::string& key) const {
  const YAML::Node node = require(key);
  const double value = number(node, key);
  if (!(value > 0.0)) fail(node, key, "must be positive, got " + formatDouble(value));
  return value;
}

std::string YamlSection::text(const std::string& key) const {
  const YAML::Node node = require(key);
  if (!node.IsScalar()) fail(node, key, "must be a string");
  return node.Scalar();
}

std::vector<double> YamlSection::numbers(const YAML::Node& node, const std::string& key, std::size_t min_count,
                                         std::size_t max_count) const {
  if (!node.IsSequence()) fail(node, key, "must be a list of numbers");
  if (node.size() < min_count || node.size() > max_count) {
    fail(node, key,
         "must have " + std::to_string(min_count) +
             (max_count != min_count ? "-" + std::to_string(max_count) : std::string()) + " values, got " +
             std::to_string(node.size()));
  }
  std::vector<double> values;
  for (const auto& item : node) values.push_back(number(item, key));
  return values;
}

}  // namespace mcvio::dataset::detail
