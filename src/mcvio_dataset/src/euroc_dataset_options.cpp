#include "mcvio/dataset/euroc_dataset_options.hpp"

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_fields.hpp"

namespace mcvio::dataset {

EurocDatasetOptions EurocDatasetOptions::fromYaml(const YAML::Node& node) {
  EurocDatasetOptions options;
  try {
    YamlFields f(node, "", "key");
    f.get("skip_bad_rows", &options.skip_bad_rows);
    f.get("max_stereo_offset_ns", &options.max_stereo_offset_ns);
    f.get("check_image_size", &options.check_image_size);
    f.rejectUnknown();
    requireOption(options.max_stereo_offset_ns >= 0, "key", "max_stereo_offset_ns", "must not be negative");
  } catch (const InputError& e) {
    throw InputError(std::string("dataset options: ") + e.what());
  }
  return options;
}

}  // namespace mcvio::dataset
