#include "mcvio/conflict/conflict_options.hpp"

#include <cmath>

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_fields.hpp"

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

void require(bool ok, const char* key, const std::string& rule, double value) {
  requireOption(ok, "conflict option", key, rule, value);
}

}  // namespace

void ConflictOptions::validate() const {
  require(horizon_frames >= 1 && horizon_frames <= 100, "horizon_frames", "must be in [1, 100]", horizon_frames);
  require(observation_sigma_px > 0, "observation_sigma_px", "must be > 0", observation_sigma_px);
  require(stereo_sigma_px > 0, "stereo_sigma_px", "must be > 0", stereo_sigma_px);
  require(velocity_sigma_mps > 0, "velocity_sigma_mps", "must be > 0", velocity_sigma_mps);
  require(attitude_sigma_rad > 0, "attitude_sigma_rad", "must be > 0", attitude_sigma_rad);
  require(landmark_attitude_sigma_rad >= 0, "landmark_attitude_sigma_rad", "must be >= 0 (0: attitude_sigma_rad)",
          landmark_attitude_sigma_rad);
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
  try {
    YamlFields f(node, "", "conflict option");
    std::string mode = toString(o.mode);
    f.get("mode", &mode);
    o.mode = resolutionModeFromString(mode, "conflict option 'mode'");
    f.get("horizon_frames", &o.horizon_frames);
    f.get("observation_sigma_px", &o.observation_sigma_px);
    f.get("stereo_sigma_px", &o.stereo_sigma_px);
    f.get("velocity_sigma_mps", &o.velocity_sigma_mps);
    f.get("attitude_sigma_rad", &o.attitude_sigma_rad);
    f.get("landmark_attitude_sigma_rad", &o.landmark_attitude_sigma_rad);
    f.get("accel_bias_sigma", &o.accel_bias_sigma);
    f.get("gyro_bias_sigma", &o.gyro_bias_sigma);
    f.get("propagated_chi2_threshold", &o.propagated_chi2_threshold);
    f.get("landmark_chi2_threshold", &o.landmark_chi2_threshold);
    f.get("min_landmarks_tested", &o.min_landmarks_tested);
    f.get("partial_min_count", &o.partial_min_count);
    f.get("partial_min_fraction", &o.partial_min_fraction);
    f.get("min_coherence", &o.min_coherence);
    f.get("coherence_sigma_m", &o.coherence_sigma_m);
    f.get("frontend_evidence", &o.frontend_evidence);
    f.get("frontend_min_count", &o.frontend_min_count);
    f.get("frontend_min_fraction", &o.frontend_min_fraction);
    f.get("frontend_marginal_score", &o.frontend_marginal_score);
    f.get("frontend_evidence_after_imu_exit", &o.frontend_evidence_after_imu_exit);
    f.get("hold_moving_min_count", &o.hold_moving_min_count);
    f.get("hold_moving_min_fraction", &o.hold_moving_min_fraction);
    f.get("frontend_agreement_ends_hold", &o.frontend_agreement_ends_hold);
    f.get("whole_view_fraction", &o.whole_view_fraction);
    f.get("warmup_frames", &o.warmup_frames);
    f.get("bias_reference_lag_frames", &o.bias_reference_lag_frames);
    f.get("bias_reference_max_change_sigmas", &o.bias_reference_max_change_sigmas);
    f.get("split_chi2_threshold", &o.split_chi2_threshold);
    f.get("split_min_frames", &o.split_min_frames);
    f.get("bias_drift_sigmas", &o.bias_drift_sigmas);
    f.get("bias_drift_arm_frames", &o.bias_drift_arm_frames);
    f.get("bias_drift_min_frames", &o.bias_drift_min_frames);
    f.get("bias_drift_fast_factor", &o.bias_drift_fast_factor);
    f.get("bias_drift_fast_frames", &o.bias_drift_fast_frames);
    f.get("bias_drift_long_frames", &o.bias_drift_long_frames);
    f.get("bias_drift_long_sigmas", &o.bias_drift_long_sigmas);
    f.get("enter_frames", &o.enter_frames);
    f.get("exit_frames", &o.exit_frames);
    f.get("exit_quiet_frames", &o.exit_quiet_frames);
    f.get("exit_quiet_score", &o.exit_quiet_score);
    f.get("onset_min_score", &o.onset_min_score);
    f.get("onset_lookback_frames", &o.onset_lookback_frames);
    f.get("selective_strikes", &o.selective_strikes);
    f.get("use_frontend_labels", &o.use_frontend_labels);
    f.get("frontend_labels_outside_conflicts", &o.frontend_labels_outside_conflicts);
    f.get("frontend_labels_outside_min_count", &o.frontend_labels_outside_min_count);
    f.get("frontend_labels_after_conflict_frames", &o.frontend_labels_after_conflict_frames);
    f.get("new_landmark_probation", &o.new_landmark_probation);
    f.get("probation_agreeing_tests", &o.probation_agreeing_tests);
    f.get("auto_min_static_landmarks", &o.auto_min_static_landmarks);
    f.get("auto_min_tested_landmarks", &o.auto_min_tested_landmarks);
    f.get("thin_view_bias_hold_landmarks", &o.thin_view_bias_hold_landmarks);
    f.get("thin_view_bias_hold_usable_tracks", &o.thin_view_bias_hold_usable_tracks);
    f.get("split_bias_hold", &o.split_bias_hold);
    f.get("frontend_conflict_keeps_history", &o.frontend_conflict_keeps_history);
    f.get("vision_depth_weighting", &o.vision_depth_weighting);
    f.get("auto_split_fraction", &o.auto_split_fraction);
    f.get("rewind_on_entry", &o.rewind_on_entry);
    f.get("rewind_frames", &o.rewind_frames);
    f.get("keep_consistent_rotation", &o.keep_consistent_rotation);
    f.get("rotation_chi2_threshold", &o.rotation_chi2_threshold);
    f.get("exit_velocity_frames", &o.exit_velocity_frames);
    f.get("exit_velocity_frames_after_hold", &o.exit_velocity_frames_after_hold);
    f.get("hold_min_secondary_speed_mps", &o.hold_min_secondary_speed_mps);
    f.get("hold_secondary_speed_fraction", &o.hold_secondary_speed_fraction);
    f.get("hold_max_speed_gain", &o.hold_max_speed_gain);
    f.get("smoothing_enabled", &o.smoothing_enabled);
    f.get("smoothing_settle_frames", &o.smoothing_settle_frames);
    f.get("exit_bias_hold_frames", &o.exit_bias_hold_frames);
    f.get("restart_on_exit", &o.restart_on_exit);
    f.get("restart_min_velocity_jump_mps", &o.restart_min_velocity_jump_mps);
    f.get("smoothing_max_acceleration_correction", &o.smoothing_max_acceleration_correction);
    f.get("smoothing_held_acceleration_sigma", &o.smoothing_held_acceleration_sigma);
    f.get("smoothing_reidentified_min_landmarks", &o.smoothing_reidentified_min_landmarks);
    f.get("smoothing_settled_velocity_sigma", &o.smoothing_settled_velocity_sigma);
    f.get("smoothing_registration_radius_m", &o.smoothing_registration_radius_m);
    f.get("smoothing_registration_tolerance_m", &o.smoothing_registration_tolerance_m);
    f.get("smoothing_registration_min_fraction", &o.smoothing_registration_min_fraction);
    f.get("smoothing_registration_max_ambiguity", &o.smoothing_registration_max_ambiguity);
    f.rejectUnknown();
    o.validate();
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  return o;
}

}  // namespace mcvio::conflict
