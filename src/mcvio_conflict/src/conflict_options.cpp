#include "mcvio/conflict/conflict_options.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"

namespace mcvio::conflict {

const char* toString(ResolutionMode mode) {
  switch (mode) {
    case ResolutionMode::kReference:
      return "reference";
    case ResolutionMode::kImu:
      return "imu";
    case ResolutionMode::kSelective:
      return "selective";
    case ResolutionMode::kAuto:
      return "auto";
  }
  return "unknown";
}

ResolutionMode resolutionModeFromString(const std::string& text, const std::string& context) {
  for (auto m : {ResolutionMode::kReference, ResolutionMode::kImu, ResolutionMode::kSelective, ResolutionMode::kAuto})
    if (text == toString(m)) return m;
  throw InputError(context + ": unknown mode '" + text + "' (expected reference, imu, selective or auto)");
}

namespace {

void require(bool ok, const char* key, const std::string& what, double value) {
  if (ok && std::isfinite(value)) return;
  std::ostringstream os;
  os << "conflict option '" << key << "' " << what << " (got " << value << ")";
  throw InputError(os.str());
}

}  // namespace

void ConflictOptions::validate() const {
  require(horizon_frames >= 1 && horizon_frames <= 100, "horizon_frames", "must be in [1, 100]", horizon_frames);
  require(observation_sigma_px > 0, "observation_sigma_px", "must be > 0", observation_sigma_px);
  require(stereo_sigma_px > 0, "stereo_sigma_px", "must be > 0", stereo_sigma_px);
  require(velocity_sigma_mps > 0, "velocity_sigma_mps", "must be > 0", velocity_sigma_mps);
  require(attitude_sigma_rad > 0, "attitude_sigma_rad", "must be > 0", attitude_sigma_rad);
  require(accel_bias_sigma > 0, "accel_bias_sigma", "must be > 0", accel_bias_sigma);
  require(gyro_bias_sigma > 0, "gyro_bias_sigma", "must be > 0", gyro_bias_sigma);
  require(propagated_chi2_threshold > 0, "propagated_chi2_threshold", "must be > 0", propagated_chi2_threshold);
  require(landmark_chi2_threshold > 0, "landmark_chi2_threshold", "must be > 0", landmark_chi2_threshold);
  require(min_landmarks_tested >= 3, "min_landmarks_tested", "must be >= 3", min_landmarks_tested);
  require(partial_min_count >= 3, "partial_min_count", "must be >= 3", partial_min_count);
  require(partial_min_fraction > 0 && partial_min_fraction <= 1, "partial_min_fraction", "must be in (0, 1]",
          partial_min_fraction);
  require(frontend_min_count >= 3, "frontend_min_count", "must be >= 3", frontend_min_count);
  require(frontend_min_fraction > 0 && frontend_min_fraction <= 1, "frontend_min_fraction", "must be in (0, 1]",
          frontend_min_fraction);
  require(frontend_marginal_score >= 1, "frontend_marginal_score", "must be >= 1 (1: off)", frontend_marginal_score);
  require(hold_moving_min_count >= 1, "hold_moving_min_count", "must be >= 1", hold_moving_min_count);
  require(hold_moving_min_fraction > 0 && hold_moving_min_fraction <= 1, "hold_moving_min_fraction",
          "must be in (0, 1]", hold_moving_min_fraction);
  require(min_coherence >= 0 && min_coherence <= 1, "min_coherence", "must be in [0, 1]", min_coherence);
  require(coherence_sigma_m > 0, "coherence_sigma_m", "must be > 0", coherence_sigma_m);
  require(whole_view_fraction > 0 && whole_view_fraction <= 1, "whole_view_fraction", "must be in (0, 1]",
          whole_view_fraction);
  require(warmup_frames >= 0, "warmup_frames", "must be >= 0", warmup_frames);
  require(bias_reference_lag_frames >= 0 && bias_reference_lag_frames <= 400, "bias_reference_lag_frames",
          "must be in [0, 400]", bias_reference_lag_frames);
  require(bias_reference_max_change_sigmas > 0, "bias_reference_max_change_sigmas", "must be > 0",
          bias_reference_max_change_sigmas);
  require(split_chi2_threshold >= 0, "split_chi2_threshold", "must be >= 0 (0: off)", split_chi2_threshold);
  require(split_min_frames >= 0 && split_min_frames <= 100, "split_min_frames", "must be in [0, 100] (0: off)",
          split_min_frames);
  require(bias_drift_sigmas >= 0, "bias_drift_sigmas", "must be >= 0 (0: off)", bias_drift_sigmas);
  require(bias_drift_arm_frames >= 0, "bias_drift_arm_frames", "must be >= 0", bias_drift_arm_frames);
  require(bias_drift_min_frames >= 1, "bias_drift_min_frames", "must be >= 1", bias_drift_min_frames);
  require(bias_drift_fast_factor == 0 || bias_drift_fast_factor >= 1, "bias_drift_fast_factor",
          "must be 0 (off) or >= 1", bias_drift_fast_factor);
  require(bias_drift_fast_frames >= 1, "bias_drift_fast_frames", "must be >= 1", bias_drift_fast_frames);
  require(bias_drift_long_frames >= 0, "bias_drift_long_frames", "must be >= 0 (0: off)", bias_drift_long_frames);
  require(bias_drift_long_sigmas > 0, "bias_drift_long_sigmas", "must be > 0", bias_drift_long_sigmas);
  require(enter_frames >= 1, "enter_frames", "must be >= 1", enter_frames);
  require(exit_frames >= 1, "exit_frames", "must be >= 1", exit_frames);
  require(exit_quiet_frames >= 0, "exit_quiet_frames", "must be >= 0 (0: off)", exit_quiet_frames);
  require(exit_quiet_score > 0 && exit_quiet_score < 1, "exit_quiet_score", "must be in (0, 1)", exit_quiet_score);
  require(onset_min_score > 0 && onset_min_score <= 1, "onset_min_score", "must be in (0, 1]", onset_min_score);
  require(onset_lookback_frames >= 0 && onset_lookback_frames <= 400, "onset_lookback_frames", "must be in [0, 400]",
          onset_lookback_frames);
  require(rotation_chi2_threshold > 0, "rotation_chi2_threshold", "must be > 0", rotation_chi2_threshold);
  require(exit_velocity_frames >= 2 && exit_velocity_frames <= 100, "exit_velocity_frames",
          "must be in [2, 100]", exit_velocity_frames);
  require(exit_velocity_frames_after_hold >= 2 && exit_velocity_frames_after_hold <= 100,
          "exit_velocity_frames_after_hold", "must be in [2, 100]", exit_velocity_frames_after_hold);
  require(rewind_frames >= 0 && rewind_frames <= 400, "rewind_frames", "must be in [0, 400]", rewind_frames);
  require(hold_min_secondary_speed_mps > 0, "hold_min_secondary_speed_mps", "must be > 0", hold_min_secondary_speed_mps);
  require(hold_secondary_speed_fraction >= 0 && hold_secondary_speed_fraction <= 1, "hold_secondary_speed_fraction",
          "must be in [0, 1]", hold_secondary_speed_fraction);
  require(hold_max_speed_gain >= 1, "hold_max_speed_gain", "must be >= 1", hold_max_speed_gain);
  require(exit_bias_hold_frames >= 0 && exit_bias_hold_frames <= 400, "exit_bias_hold_frames", "must be in [0, 400]",
          exit_bias_hold_frames);
  require(restart_min_velocity_jump_mps >= 0, "restart_min_velocity_jump_mps", "must be >= 0",
          restart_min_velocity_jump_mps);
  require(smoothing_settle_frames >= 1 && smoothing_settle_frames <= 400, "smoothing_settle_frames", "must be in [1, 400]",
          smoothing_settle_frames);
  require(smoothing_max_acceleration_correction > 0, "smoothing_max_acceleration_correction", "must be > 0",
          smoothing_max_acceleration_correction);
  require(smoothing_held_acceleration_sigma > 0, "smoothing_held_acceleration_sigma", "must be > 0",
          smoothing_held_acceleration_sigma);
  require(smoothing_reidentified_min_landmarks >= 0, "smoothing_reidentified_min_landmarks", "must be >= 0",
          smoothing_reidentified_min_landmarks);
  require(smoothing_settled_velocity_sigma > 0, "smoothing_settled_velocity_sigma", "must be > 0",
          smoothing_settled_velocity_sigma);
  require(smoothing_registration_radius_m >= 0 && smoothing_registration_radius_m <= 50,
          "smoothing_registration_radius_m", "must be in [0, 50]", smoothing_registration_radius_m);
  require(smoothing_registration_tolerance_m > 0 && smoothing_registration_tolerance_m <= 1,
          "smoothing_registration_tolerance_m", "must be in (0, 1]", smoothing_registration_tolerance_m);
  require(smoothing_registration_radius_m <= 2000.0 * smoothing_registration_tolerance_m,
          "smoothing_registration_tolerance_m", "must be at least smoothing_registration_radius_m / 2000",
          smoothing_registration_tolerance_m);
  require(smoothing_registration_min_fraction > 0 && smoothing_registration_min_fraction <= 1,
          "smoothing_registration_min_fraction", "must be in (0, 1]", smoothing_registration_min_fraction);
  require(smoothing_registration_max_ambiguity > 0 && smoothing_registration_max_ambiguity < 1,
          "smoothing_registration_max_ambiguity", "must be in (0, 1)", smoothing_registration_max_ambiguity);
  require(auto_split_fraction > 0 && auto_split_fraction <= 1, "auto_split_fraction", "must be in (0, 1]",
          auto_split_fraction);
  require(selective_strikes >= 1, "selective_strikes", "must be >= 1", selective_strikes);
  require(frontend_labels_outside_min_count >= 1, "frontend_labels_outside_min_count", "must be >= 1",
          frontend_labels_outside_min_count);
  require(frontend_labels_after_conflict_frames >= 0, "frontend_labels_after_conflict_frames", "must be >= 0",
          frontend_labels_after_conflict_frames);
  require(probation_agreeing_tests >= 1, "probation_agreeing_tests", "must be >= 1", probation_agreeing_tests);
  require(auto_min_static_landmarks >= 0, "auto_min_static_landmarks", "must be >= 0", auto_min_static_landmarks);
  require(auto_min_tested_landmarks >= 0, "auto_min_tested_landmarks", "must be >= 0",
          auto_min_tested_landmarks);
  require(thin_view_bias_hold_landmarks >= 0, "thin_view_bias_hold_landmarks", "must be >= 0 (0: off)",
          thin_view_bias_hold_landmarks);
  require(thin_view_bias_hold_usable_tracks >= 0, "thin_view_bias_hold_usable_tracks", "must be >= 0 (0: off)",
          thin_view_bias_hold_usable_tracks);
}

ConflictOptions ConflictOptions::fromYaml(const YAML::Node& node, const std::string& context) {
  ConflictOptions o;
  if (!node || node.IsNull()) return o;
  if (!node.IsMap()) throw InputError(context + ": the conflict section must be a map");
  std::set<std::string> known;
  auto read = [&](const char* key, auto* value) {
    known.insert(key);
    const YAML::Node v = node[key];
    if (!v) return;
    try {
      *value = v.as<std::remove_pointer_t<decltype(value)>>();
    } catch (const YAML::Exception& e) {
      throw InputError(context + ": key 'conflict." + key + "' has an invalid value (" + e.what() + ")");
    }
  };
  std::string mode = toString(o.mode);
  read("mode", &mode);
  o.mode = resolutionModeFromString(mode, context + ": key 'conflict.mode'");
  read("horizon_frames", &o.horizon_frames);
  read("observation_sigma_px", &o.observation_sigma_px);
  read("stereo_sigma_px", &o.stereo_sigma_px);
  read("velocity_sigma_mps", &o.velocity_sigma_mps);
  read("attitude_sigma_rad", &o.attitude_sigma_rad);
  read("accel_bias_sigma", &o.accel_bias_sigma);
  read("gyro_bias_sigma", &o.gyro_bias_sigma);
  read("propagated_chi2_threshold", &o.propagated_chi2_threshold);
  read("landmark_chi2_threshold", &o.landmark_chi2_threshold);
  read("min_landmarks_tested", &o.min_landmarks_tested);
  read("partial_min_count", &o.partial_min_count);
  read("partial_min_fraction", &o.partial_min_fraction);
  read("min_coherence", &o.min_coherence);
  read("coherence_sigma_m", &o.coherence_sigma_m);
  read("frontend_evidence", &o.frontend_evidence);
  read("frontend_min_count", &o.frontend_min_count);
  read("frontend_min_fraction", &o.frontend_min_fraction);
  read("frontend_marginal_score", &o.frontend_marginal_score);
  read("hold_moving_min_count", &o.hold_moving_min_count);
  read("hold_moving_min_fraction", &o.hold_moving_min_fraction);
  read("frontend_agreement_ends_hold", &o.frontend_agreement_ends_hold);
  read("whole_view_fraction", &o.whole_view_fraction);
  read("warmup_frames", &o.warmup_frames);
  read("bias_reference_lag_frames", &o.bias_reference_lag_frames);
  read("bias_reference_max_change_sigmas", &o.bias_reference_max_change_sigmas);
  read("split_chi2_threshold", &o.split_chi2_threshold);
  read("split_min_frames", &o.split_min_frames);
  read("bias_drift_sigmas", &o.bias_drift_sigmas);
  read("bias_drift_arm_frames", &o.bias_drift_arm_frames);
  read("bias_drift_min_frames", &o.bias_drift_min_frames);
  read("bias_drift_fast_factor", &o.bias_drift_fast_factor);
  read("bias_drift_fast_frames", &o.bias_drift_fast_frames);
  read("bias_drift_long_frames", &o.bias_drift_long_frames);
  read("bias_drift_long_sigmas", &o.bias_drift_long_sigmas);
  read("enter_frames", &o.enter_frames);
  read("exit_frames", &o.exit_frames);
  read("exit_quiet_frames", &o.exit_quiet_frames);
  read("exit_quiet_score", &o.exit_quiet_score);
  read("onset_min_score", &o.onset_min_score);
  read("onset_lookback_frames", &o.onset_lookback_frames);
  read("selective_strikes", &o.selective_strikes);
  read("use_frontend_labels", &o.use_frontend_labels);
  read("frontend_labels_outside_conflicts", &o.frontend_labels_outside_conflicts);
  read("frontend_labels_outside_min_count", &o.frontend_labels_outside_min_count);
  read("frontend_labels_after_conflict_frames", &o.frontend_labels_after_conflict_frames);
  read("new_landmark_probation", &o.new_landmark_probation);
  read("probation_agreeing_tests", &o.probation_agreeing_tests);
  read("auto_min_static_landmarks", &o.auto_min_static_landmarks);
  read("auto_min_tested_landmarks", &o.auto_min_tested_landmarks);
  read("thin_view_bias_hold_landmarks", &o.thin_view_bias_hold_landmarks);
  read("thin_view_bias_hold_usable_tracks", &o.thin_view_bias_hold_usable_tracks);
  read("split_bias_hold", &o.split_bias_hold);
  read("vision_depth_weighting", &o.vision_depth_weighting);
  read("auto_split_fraction", &o.auto_split_fraction);
  read("rewind_on_entry", &o.rewind_on_entry);
  read("rewind_frames", &o.rewind_frames);
  read("keep_consistent_rotation", &o.keep_consistent_rotation);
  read("rotation_chi2_threshold", &o.rotation_chi2_threshold);
  read("exit_velocity_frames", &o.exit_velocity_frames);
  read("exit_velocity_frames_after_hold", &o.exit_velocity_frames_after_hold);
  read("hold_min_secondary_speed_mps", &o.hold_min_secondary_speed_mps);
  read("hold_secondary_speed_fraction", &o.hold_secondary_speed_fraction);
  read("hold_max_speed_gain", &o.hold_max_speed_gain);
  read("smoothing_enabled", &o.smoothing_enabled);
  read("smoothing_settle_frames", &o.smoothing_settle_frames);
  read("exit_bias_hold_frames", &o.exit_bias_hold_frames);
  read("restart_on_exit", &o.restart_on_exit);
  read("restart_min_velocity_jump_mps", &o.restart_min_velocity_jump_mps);
  read("smoothing_max_acceleration_correction", &o.smoothing_max_acceleration_correction);
  read("smoothing_held_acceleration_sigma", &o.smoothing_held_acceleration_sigma);
  read("smoothing_reidentified_min_landmarks", &o.smoothing_reidentified_min_landmarks);
  read("smoothing_settled_velocity_sigma", &o.smoothing_settled_velocity_sigma);
  read("smoothing_registration_radius_m", &o.smoothing_registration_radius_m);
  read("smoothing_registration_tolerance_m", &o.smoothing_registration_tolerance_m);
  read("smoothing_registration_min_fraction", &o.smoothing_registration_min_fraction);
  read("smoothing_registration_max_ambiguity", &o.smoothing_registration_max_ambiguity);
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    if (known.count(key) == 0) throw InputError(context + ": unknown conflict option '" + key + "'");
  }
  try {
    o.validate();
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  return o;
}

}  // namespace mcvio::conflict
