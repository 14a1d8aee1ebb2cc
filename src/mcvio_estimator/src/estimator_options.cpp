#include "mcvio/estimator/estimator_options.hpp"

#include <cmath>

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_fields.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::estimator {

namespace {

void require(bool ok, const char* key, const std::string& rule, double value) {
  requireOption(ok, "estimator option", key, rule, value);
}

}  // namespace

void EstimatorOptions::validate() const {
  // Upper bounds keep a typo from allocating the window's pools until the machine runs out.
  require(imu_window_size >= 2 && imu_window_size <= 1000, "imu_window_size", "must be in [2, 1000]",
          imu_window_size);
  require(keyframe_window_size >= 1 && keyframe_window_size <= 1000, "keyframe_window_size",
          "must be in [1, 1000]", keyframe_window_size);
  require(keyframe_parallax_px > 0, "keyframe_parallax_px", "must be > 0", keyframe_parallax_px);
  require(keyframe_tracked_fraction > 0 && keyframe_tracked_fraction <= 1, "keyframe_tracked_fraction",
          "must be in (0, 1]", keyframe_tracked_fraction);
  require(observation_sigma_px > 0, "observation_sigma_px", "must be > 0", observation_sigma_px);
  require(robust_loss_scale_px > 0, "robust_loss_scale_px", "must be > 0", robust_loss_scale_px);
  require(outlier_threshold_px > 0, "outlier_threshold_px", "must be > 0", outlier_threshold_px);
  require(min_depth_m > 0, "min_depth_m", "must be > 0", min_depth_m);
  require(max_depth_m > min_depth_m, "max_depth_m", "must be > min_depth_m", max_depth_m);
  require(min_stereo_disparity_px >= 0, "min_stereo_disparity_px", "must be >= 0", min_stereo_disparity_px);
  require(gravity_magnitude > 0, "gravity_magnitude", "must be > 0", gravity_magnitude);
  require(imu_noise_inflation > 0, "imu_noise_inflation", "must be > 0", imu_noise_inflation);
  require(imu_random_walk_inflation > 0, "imu_random_walk_inflation", "must be > 0", imu_random_walk_inflation);
  require(repropagate_gyro_bias_change > 0, "repropagate_gyro_bias_change", "must be > 0",
          repropagate_gyro_bias_change);
  require(repropagate_accel_bias_change > 0, "repropagate_accel_bias_change", "must be > 0",
          repropagate_accel_bias_change);
  require(max_imu_gap_s > 0, "max_imu_gap_s", "must be > 0", max_imu_gap_s);
  require(max_iterations >= 1 && max_iterations <= 10000, "max_iterations", "must be in [1, 10000]", max_iterations);
  require(function_tolerance > 0 && function_tolerance < 1, "function_tolerance", "must be in (0, 1)",
          function_tolerance);
  require(conflict_function_tolerance > 0 && conflict_function_tolerance < 1, "conflict_function_tolerance",
          "must be in (0, 1)", conflict_function_tolerance);
  require(model_agreement_settle_s >= 0 && std::isfinite(model_agreement_settle_s), "model_agreement_settle_s",
          "must be >= 0", model_agreement_settle_s);
  require(max_solver_time_s > 0, "max_solver_time_s", "must be > 0", max_solver_time_s);
  require(num_threads >= 1 && num_threads <= 1024, "num_threads", "must be in [1, 1024]", num_threads);
  require(init_window_s > 0, "init_window_s", "must be > 0", init_window_s);
  require(static_gyro_std_max > 0, "static_gyro_std_max", "must be > 0", static_gyro_std_max);
  require(static_accel_std_max > 0, "static_accel_std_max", "must be > 0", static_accel_std_max);
  require(init_position_sigma > 0, "init_position_sigma", "must be > 0", init_position_sigma);
  require(init_yaw_sigma > 0, "init_yaw_sigma", "must be > 0", init_yaw_sigma);
  require(init_roll_pitch_sigma > 0, "init_roll_pitch_sigma", "must be > 0", init_roll_pitch_sigma);
  require(init_roll_pitch_sigma_moving > 0, "init_roll_pitch_sigma_moving", "must be > 0",
          init_roll_pitch_sigma_moving);
  require(init_velocity_sigma_static > 0, "init_velocity_sigma_static", "must be > 0", init_velocity_sigma_static);
  require(init_velocity_sigma_moving > 0, "init_velocity_sigma_moving", "must be > 0", init_velocity_sigma_moving);
  require(init_gyro_bias_sigma_static > 0, "init_gyro_bias_sigma_static", "must be > 0", init_gyro_bias_sigma_static);
  require(init_gyro_bias_sigma_moving > 0, "init_gyro_bias_sigma_moving", "must be > 0", init_gyro_bias_sigma_moving);
  require(init_accel_bias_sigma > 0, "init_accel_bias_sigma", "must be > 0", init_accel_bias_sigma);
  require(zero_velocity_max_disparity_px >= 0, "zero_velocity_max_disparity_px", "must be >= 0",
          zero_velocity_max_disparity_px);
  require(zero_velocity_gyro_std_max >= 0, "zero_velocity_gyro_std_max", "must be >= 0", zero_velocity_gyro_std_max);
  require(zero_velocity_accel_std_max >= 0, "zero_velocity_accel_std_max", "must be >= 0",
          zero_velocity_accel_std_max);
  require(zero_velocity_sigma > 0, "zero_velocity_sigma", "must be > 0", zero_velocity_sigma);
  require(max_speed_mps > 0, "max_speed_mps", "must be > 0", max_speed_mps);
  require(max_gyro_bias > 0, "max_gyro_bias", "must be > 0", max_gyro_bias);
  require(max_accel_bias > 0, "max_accel_bias", "must be > 0", max_accel_bias);
  require(max_position_jump_m > 0, "max_position_jump_m", "must be > 0", max_position_jump_m);
  require(max_time_without_vision_s > 0, "max_time_without_vision_s", "must be > 0", max_time_without_vision_s);
  conflict.validate();
}

EstimatorOptions EstimatorOptions::fromYaml(const YAML::Node& node, const std::string& context) {
  EstimatorOptions o;
  YAML::Node conflict_section;
  try {
    YamlFields f(node, "", "estimator option");
    conflict_section = f.child("conflict");
    f.get("imu_window_size", &o.imu_window_size);
    f.get("keyframe_window_size", &o.keyframe_window_size);
    f.get("keyframe_parallax_px", &o.keyframe_parallax_px);
    f.get("keyframe_tracked_fraction", &o.keyframe_tracked_fraction);
    f.get("observation_sigma_px", &o.observation_sigma_px);
    if (f.has("pixel_scale")) {
      std::string scale;
      f.get("pixel_scale", &scale);
      o.pixel_scale = pixelScaleFromString(scale);
    }
    if (f.has("robust_loss")) {
      std::string loss;
      f.get("robust_loss", &loss);
      if (loss == "none")
        o.robust_loss = RobustLoss::kNone;
      else if (loss == "huber")
        o.robust_loss = RobustLoss::kHuber;
      else if (loss == "cauchy")
        o.robust_loss = RobustLoss::kCauchy;
      else
        throw InputError("estimator option 'robust_loss' must be none, huber or cauchy (got '" + loss + "')");
    }
    f.get("robust_loss_scale_px", &o.robust_loss_scale_px);
    f.get("outlier_threshold_px", &o.outlier_threshold_px);
    f.get("outlier_drops_landmark", &o.outlier_drops_landmark);
    f.get("min_depth_m", &o.min_depth_m);
    f.get("max_depth_m", &o.max_depth_m);
    f.get("min_stereo_disparity_px", &o.min_stereo_disparity_px);
    f.get("right_camera_in_all_frames", &o.right_camera_in_all_frames);
    f.get("marginalize_tracked_landmark_history", &o.marginalize_tracked_landmark_history);
    f.get("gravity_magnitude", &o.gravity_magnitude);
    f.get("imu_noise_inflation", &o.imu_noise_inflation);
    f.get("imu_random_walk_inflation", &o.imu_random_walk_inflation);
    f.get("repropagate_gyro_bias_change", &o.repropagate_gyro_bias_change);
    f.get("repropagate_accel_bias_change", &o.repropagate_accel_bias_change);
    f.get("max_imu_gap_s", &o.max_imu_gap_s);
    f.get("max_iterations", &o.max_iterations);
    f.get("function_tolerance", &o.function_tolerance);
    f.get("conflict_function_tolerance", &o.conflict_function_tolerance);
    f.get("stop_on_model_agreement", &o.stop_on_model_agreement);
    f.get("model_agreement_settle_s", &o.model_agreement_settle_s);
    f.get("max_solver_time_s", &o.max_solver_time_s);
    f.get("num_threads", &o.num_threads);
    f.get("compute_covariance", &o.compute_covariance);
    f.get("init_window_s", &o.init_window_s);
    f.get("static_gyro_std_max", &o.static_gyro_std_max);
    f.get("static_accel_std_max", &o.static_accel_std_max);
    f.get("init_position_sigma", &o.init_position_sigma);
    f.get("init_yaw_sigma", &o.init_yaw_sigma);
    f.get("init_roll_pitch_sigma", &o.init_roll_pitch_sigma);
    f.get("init_roll_pitch_sigma_moving", &o.init_roll_pitch_sigma_moving);
    f.get("init_velocity_sigma_static", &o.init_velocity_sigma_static);
    f.get("init_velocity_sigma_moving", &o.init_velocity_sigma_moving);
    f.get("init_gyro_bias_sigma_static", &o.init_gyro_bias_sigma_static);
    f.get("init_gyro_bias_sigma_moving", &o.init_gyro_bias_sigma_moving);
    f.get("init_accel_bias_sigma", &o.init_accel_bias_sigma);
    f.get("zero_velocity_enabled", &o.zero_velocity_enabled);
    f.get("zero_velocity_max_disparity_px", &o.zero_velocity_max_disparity_px);
    f.get("zero_velocity_gyro_std_max", &o.zero_velocity_gyro_std_max);
    f.get("zero_velocity_accel_std_max", &o.zero_velocity_accel_std_max);
    f.get("zero_velocity_sigma", &o.zero_velocity_sigma);
    f.get("max_speed_mps", &o.max_speed_mps);
    f.get("max_gyro_bias", &o.max_gyro_bias);
    f.get("max_accel_bias", &o.max_accel_bias);
    f.get("max_position_jump_m", &o.max_position_jump_m);
    f.get("max_time_without_vision_s", &o.max_time_without_vision_s);
    f.rejectUnknown();
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  // Outside the try: its errors name the context themselves ("conflict option 'key'").
  o.conflict = conflict::ConflictOptions::fromYaml(conflict_section, context);
  try {
    o.validate();
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  return o;
}

EstimatorOptions EstimatorOptions::fromYamlFile(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "estimator options file");
  if (root.IsMap() && root["estimator"]) return fromYaml(root["estimator"], path);
  return fromYaml(root, path);
}

}  // namespace mcvio::estimator
