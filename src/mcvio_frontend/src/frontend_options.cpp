#include "mcvio/frontend/frontend_options.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_fields.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::frontend {
namespace {

void require(bool ok, const std::string& key, const std::string& rule) {
  requireOption(ok, "frontend option", key, rule);
}

}  // namespace

void FrontendOptions::validate() const {
  // Upper bounds keep a typo (an extra digit or three) from allocating or looping for hours.
  require(max_features > 0 && max_features <= 100000, "max_features", "must be in [1, 100000]");
  require(std::isfinite(moving_track_budget_share) && moving_track_budget_share >= 0 && moving_track_budget_share <= 1,
          "moving_track_budget_share", "must be in [0, 1]");
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
  require(klt_max_iterations > 0 && klt_max_iterations <= 1000, "klt_max_iterations", "must be in [1, 1000]");
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
  require(ransac_iterations > 0 && ransac_iterations <= 100000, "ransac_iterations", "must be in [1, 100000]");
  require(min_tracks_for_check >= 5, "min_tracks_for_check", "must be >= 5");
  require(reidentify_min_age_s >= 0 && reidentify_min_age_s < reidentify_max_age_s, "reidentify_min_age_s",
          "must be >= 0 and below reidentify_max_age_s");
  require(reidentify_max_age_s > 0 && reidentify_max_age_s <= 600, "reidentify_max_age_s", "must be in (0, 600]");
  require(reidentify_max_hamming >= 0 && reidentify_max_hamming <= 256, "reidentify_max_hamming",
          "must be in [0, 256]");
  require(reidentify_ratio > 0 && reidentify_ratio <= 1, "reidentify_ratio", "must be in (0, 1]");
  require(history_length >= 1 && history_length <= 10000, "history_length", "must be in [1, 10000]");
}

FrontendOptions FrontendOptions::fromYaml(const YAML::Node& node, const std::string& context) {
  FrontendOptions o;
  try {
    YamlFields f(node, "", "frontend option");
    f.get("max_features", &o.max_features);
    f.get("moving_track_budget_share", &o.moving_track_budget_share);
    f.get("grid_cols", &o.grid_cols);
    f.get("grid_rows", &o.grid_rows);
    f.get("min_distance_px", &o.min_distance_px);
    f.get("fast_threshold", &o.fast_threshold);
    f.get("fast_min_threshold", &o.fast_min_threshold);
    f.get("border_px", &o.border_px);
    f.get("subpixel_refinement", &o.subpixel_refinement);
    f.get("pyramid_levels", &o.pyramid_levels);
    f.get("check_pyramid_levels", &o.check_pyramid_levels);
    f.get("window_size", &o.window_size);
    f.get("klt_max_iterations", &o.klt_max_iterations);
    f.get("klt_epsilon", &o.klt_epsilon);
    f.get("fb_threshold_px", &o.fb_threshold_px);
    f.get("use_gyro_prediction", &o.use_gyro_prediction);
    f.get("exposure_normalization", &o.exposure_normalization);
    f.get("normalization_block_px", &o.normalization_block_px);
    f.get("max_imu_gap_ns", &o.max_imu_gap_ns);
    f.get("stereo_fb_threshold_px", &o.stereo_fb_threshold_px);
    f.get("stereo_epipolar_threshold_px", &o.stereo_epipolar_threshold_px);
    f.get("stereo_prediction_tolerance_px", &o.stereo_prediction_tolerance_px);
    f.get("min_depth_m", &o.min_depth_m);
    f.get("max_depth_m", &o.max_depth_m);
    f.get("ransac_threshold_px", &o.ransac_threshold_px);
    if (f.has("pixel_scale")) {
      std::string scale;
      f.get("pixel_scale", &scale);
      o.pixel_scale = pixelScaleFromString(scale);
    }
    f.get("ransac_iterations", &o.ransac_iterations);
    f.get("min_tracks_for_check", &o.min_tracks_for_check);
    f.get("ransac_seed", &o.ransac_seed);
    f.get("reidentify_lost_tracks", &o.reidentify_lost_tracks);
    f.get("reidentify_min_age_s", &o.reidentify_min_age_s);
    f.get("reidentify_max_age_s", &o.reidentify_max_age_s);
    f.get("reidentify_max_hamming", &o.reidentify_max_hamming);
    f.get("reidentify_ratio", &o.reidentify_ratio);
    f.get("mask0", &o.mask0);
    f.get("mask1", &o.mask1);
    f.get("history_length", &o.history_length);
    f.rejectUnknown();
    o.validate();
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  return o;
}

FrontendOptions FrontendOptions::fromFile(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "frontend options file");
  FrontendOptions o = root.IsMap() && root["frontend"] ? fromYaml(root["frontend"], path) : fromYaml(root, path);
  o.resolvePathsFrom(std::filesystem::path(path).parent_path().string());
  return o;
}

void FrontendOptions::resolvePathsFrom(const std::string& dir) {
  for (std::string* mask : {&mask0, &mask1})
    if (!mask->empty() && std::filesystem::path(*mask).is_relative()) *mask = (std::filesystem::path(dir) / *mask).string();
}

}  // namespace mcvio::frontend
