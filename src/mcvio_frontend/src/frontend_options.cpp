#include "mcvio/frontend/frontend_options.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>
#include <map>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::frontend {
namespace {

void require(bool ok, const std::string& key, const std::string& rule) {
  if (!ok) throw InputError("frontend option '" + key + "' " + rule);
}

template <typename T>
void readInto(const YAML::Node& value, const std::string& context, const std::string& key, T* out) {
  try {
    *out = value.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(context + ": frontend option '" + key + "' has the wrong type");
  }
}

}  // namespace

void FrontendOptions::validate() const {
  require(max_features > 0, "max_features", "must be > 0");
  require(grid_cols > 0 && grid_cols <= 64, "grid_cols", "must be in [1, 64]");
  require(grid_rows > 0 && grid_rows <= 64, "grid_rows", "must be in [1, 64]");
  require(std::isfinite(min_distance_px) && min_distance_px >= 1.0, "min_distance_px",
          "must be >= 1");
  require(fast_threshold > 0 && fast_threshold < 255, "fast_threshold", "must be in [1, 254]");
  require(fast_min_threshold > 0 && fast_min_threshold <= fast_threshold, "fast_min_threshold",
          "must be in [1, fast_threshold]");
  require(border_px >= 0 && border_px < 100, "border_px", "must be in [0, 100)");
  require(pyramid_levels >= 0 && pyramid_levels <= 8, "pyramid_levels", "must be in [0, 8]");
  require(check_pyramid_levels >= 0 && check_pyramid_levels <= 8, "check_pyramid_levels",
          "must be in [0, 8]");
  require(window_size >= 5 && window_size <= 61 && window_size % 2 == 1, "window_size",
          "must be odd and in [5, 61]");
  require(klt_max_iterations > 0, "klt_max_iterations", "must be > 0");
  require(klt_epsilon > 0 && std::isfinite(klt_epsilon), "klt_epsilon", "must be > 0");
  require(fb_threshold_px > 0 && std::isfinite(fb_threshold_px), "fb_threshold_px", "must be > 0");
  require(exposure_normalization == "none" || exposure_normalization == "global" ||
              exposure_normalization == "local",
          "exposure_normalization",
          "must be none, global or local, got '" + exposure_normalization + "'");
  require(normalization_block_px >= 8 && normalization_block_px <= 256, "normalization_block_px",
          "must be in [8, 256]");
  require(max_imu_gap_ns > 0, "max_imu_gap_ns", "must be > 0");
  require(stereo_fb_threshold_px > 0 && std::isfinite(stereo_fb_threshold_px),
          "stereo_fb_threshold_px", "must be > 0");
  require(stereo_epipolar_threshold_px > 0 && std::isfinite(stereo_epipolar_threshold_px),
          "stereo_epipolar_threshold_px", "must be > 0");
  require(stereo_prediction_tolerance_px >= 0 && std::isfinite(stereo_prediction_tolerance_px),
          "stereo_prediction_tolerance_px", "must be >= 0");
  require(min_depth_m > 0 && std::isfinite(min_depth_m), "min_depth_m", "must be > 0");
  require(max_depth_m > min_depth_m && std::isfinite(max_depth_m), "max_depth_m",
          "must be > min_depth_m");
  require(ransac_threshold_px > 0 && std::isfinite(ransac_threshold_px), "ransac_threshold_px",
          "must be > 0");
  require(ransac_iterations > 0, "ransac_iterations", "must be > 0");
  require(min_tracks_for_check >= 5, "min_tracks_for_check", "must be >= 5");
  require(reidentify_min_age_s >= 0 && reidentify_min_age_s < reidentify_max_age_s, "reidentify_min_age_s",
          "must be >= 0 and below reidentify_max_age_s");
  require(reidentify_max_age_s > 0 && reidentify_max_age_s <= 600, "reidentify_max_age_s", "must be in (0, 600]");
  require(reidentify_max_hamming >= 0 && reidentify_max_hamming <= 256, "reidentify_max_hamming",
          "must be in [0, 256]");
  require(reidentify_ratio > 0 && reidentify_ratio <= 1, "reidentify_ratio", "must be in (0, 1]");
  require(history_length >= 1, "history_length", "must be >= 1");
}

FrontendOptions FrontendOptions::fromYaml(const YAML::Node& node, const std::string& context) {
  FrontendOptions o;
  if (!node || node.IsNull()) return o;
  if (!node.IsMap()) throw InputError(context + ": frontend options must be a YAML map");
  using Setter = std::function<void(const YAML::Node&, const std::string&)>;
  auto bind = [&](auto* field) -> Setter {
    return [field, &context](const YAML::Node& v, const std::string& key) {
      readInto(v, context, key, field);
    };
  };
  const std::map<std::string, Setter> setters = {
      {"max_features", bind(&o.max_features)},
      {"grid_cols", bind(&o.grid_cols)},
      {"grid_rows", bind(&o.grid_rows)},
      {"min_distance_px", bind(&o.min_distance_px)},
      {"fast_threshold", bind(&o.fast_threshold)},
      {"fast_min_threshold", bind(&o.fast_min_threshold)},
      {"border_px", bind(&o.border_px)},
      {"subpixel_refinement", bind(&o.subpixel_refinement)},
      {"pyramid_levels", bind(&o.pyramid_levels)},
      {"check_pyramid_levels", bind(&o.check_pyramid_levels)},
      {"window_size", bind(&o.window_size)},
      {"klt_max_iterations", bind(&o.klt_max_iterations)},
      {"klt_epsilon", bind(&o.klt_epsilon)},
      {"fb_threshold_px", bind(&o.fb_threshold_px)},
      {"use_gyro_prediction", bind(&o.use_gyro_prediction)},
      {"exposure_normalization", bind(&o.exposure_normalization)},
      {"normalization_block_px", bind(&o.normalization_block_px)},
      {"max_imu_gap_ns", bind(&o.max_imu_gap_ns)},
      {"stereo_fb_threshold_px", bind(&o.stereo_fb_threshold_px)},
      {"stereo_epipolar_threshold_px", bind(&o.stereo_epipolar_threshold_px)},
      {"stereo_prediction_tolerance_px", bind(&o.stereo_prediction_tolerance_px)},
      {"min_depth_m", bind(&o.min_depth_m)},
      {"max_depth_m", bind(&o.max_depth_m)},
      {"ransac_threshold_px", bind(&o.ransac_threshold_px)},
      {"ransac_iterations", bind(&o.ransac_iterations)},
      {"min_tracks_for_check", bind(&o.min_tracks_for_check)},
      {"ransac_seed", bind(&o.ransac_seed)},
      {"reidentify_lost_tracks", bind(&o.reidentify_lost_tracks)},
      {"reidentify_min_age_s", bind(&o.reidentify_min_age_s)},
      {"reidentify_max_age_s", bind(&o.reidentify_max_age_s)},
      {"reidentify_max_hamming", bind(&o.reidentify_max_hamming)},
      {"reidentify_ratio", bind(&o.reidentify_ratio)},
      {"history_length", bind(&o.history_length)},
  };
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    const auto it = setters.find(key);
    if (it == setters.end()) throw InputError(context + ": unknown frontend option '" + key + "'");
    it->second(kv.second, key);
  }
  try {
    o.validate();
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  return o;
}

FrontendOptions FrontendOptions::fromFile(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "frontend options file");
  if (root.IsMap() && root["frontend"]) return fromYaml(root["frontend"], path);
  return fromYaml(root, path);
}

}  // namespace mcvio::frontend
