#include "mcvio/dataset/euroc_dataset_options.hpp"

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"

namespace mcvio::dataset {

namespace {

template <typename T>
void readKey(const YAML::Node& node, const char* key, T* value) {
  const YAML::Node item = node[key];
  if (!item) return;
  try {
    *value = item.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(std::string("dataset options: key '") + key + "' has an invalid value '" +
                     (item.IsScalar() ? item.Scalar() : std::string("<not a scalar>")) + "'");
  }
}

}  // namespace

EurocDatasetOptions EurocDatasetOptions::fromYaml(const YAML::Node& node) {
  EurocDatasetOptions options;
  if (!node) return options;
  if (!node.IsMap()) throw InputError("dataset options: expected a map of keys");
  for (const auto& item : node) {
    const std::string key =
        item.first.IsScalar() ? item.first.Scalar() : std::string("<not a scalar>");
    if (key != "skip_bad_rows" && key != "max_stereo_offset_ns" && key != "check_image_size") {
      throw InputError("dataset options: unknown key '" + key + "'");
    }
  }
  readKey(node, "skip_bad_rows", &options.skip_bad_rows);
  readKey(node, "max_stereo_offset_ns", &options.max_stereo_offset_ns);
  readKey(node, "check_image_size", &options.check_image_size);
  if (options.max_stereo_offset_ns < 0) {
    throw InputError("dataset options: key 'max_stereo_offset_ns' must not be negative");
  }
  return options;
}

}  // namespace mcvio::dataset
