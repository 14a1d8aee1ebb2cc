#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/time.hpp"
#include "synthetic_vio_sequence.hpp"

namespace mcvio::estimator {
namespace {

using testing::generateSequence;
using testing::runEstimator;
using testing::SyntheticConfig;
using testing::SyntheticSequence;

// Ideal features (perfect association, 1 px noise), EuRoC IMU noise, 20 s with a still start.
// The 60 s figure is in bench_sliding_window_estimator.
TEST(SlidingWindowEstimator, AccuracyOnSyntheticSequence) {
  SyntheticConfig cfg;
  cfg.duration_s = 20.0;
  const auto seq = generateSequence(cfg);
  const auto res = runEstimator(seq, EstimatorOptions{});
  std::printf("20 s synthetic: tracked %d/%zu frames, ATE %.4f m, mean position NEES %.3f, max error %.4f m, median %.2f ms\n",
              res.tracked_frames, seq.frames.size(), res.ate_m, res.mean_position_nees, res.max_abs_position_error_m,
              res.median_total_ms);
  EXPECT_EQ(res.resets, 0);
  // Everything after the 1 s of IMU history the initialisation waits for is tracked.
  EXPECT_GE(res.tracked_frames, static_cast<int>(seq.frames.size()) - 21);
  EXPECT_LE(res.ate_m, 0.05);
  EXPECT_LE(res.max_abs_position_error_m, 0.15);
  // Static initialisation: gyro bias from stillness, roll/pitch from gravity.
  const auto& first = res.outputs[20];
  ASSERT_TRUE(first.frame_accepted);
  EXPECT_LT((first.bias.gyro - seq.truth[20].bg).norm(), 2e-3);
  const Eigen::Vector3d z_est = first.q_WB * Eigen::Vector3d::UnitZ(), z_true = seq.truth[20].q * Eigen::Vector3d::UnitZ();
  EXPECT_LT(std::acos(std::min(1.0, z_est.dot(z_true))), 0.02);
}

// Position NEES over a few independent runs (one run's time average is dominated by a single
// drift realisation, so several seeds are averaged).
TEST(SlidingWindowEstimator, PositionNeesIsConsistent) {
  double nees = 0;
  const int runs = 3;
  for (int s = 0; s < runs; ++s) {
    SyntheticConfig cfg;
    cfg.duration_s = 12.0;
    cfg.seed = 100 + static_cast<std::uint32_t>(s);
    const auto res = runEstimator(generateSequence(cfg), EstimatorOptions{});
    std::printf("seed %u: ATE %.4f m, mean position NEES %.3f\n", cfg.seed, res.ate_m, res.mean_position_nees);
    nees += res.mean_position_nees / runs;
  }
  std::printf("mean position NEES over %d runs: %.3f (3 = consistent)\n", runs, nees);
  // 1.93 when the covariance dropped the weak directions with the solver's prior; 2.55 with them.
  EXPECT_GT(nees, 1.0);
  EXPECT_LT(nees, 6.0);
}

// Tracks that slide off their corners: from 6 s on, every tenth track drifts 1 px per frame to
// the right in both images. Each new observation of such a track is an outlier after the solve;
// dropping only that observation leaves the landmark to pull the next solve as well.
TEST(SlidingWindowEstimator, AnOutlierTakesItsSlidingLandmarkWithIt) {
  SyntheticConfig cfg;
  cfg.duration_s = 12.0;
  auto seq = generateSequence(cfg);
  const Timestamp slide_from = seq.frames.front().t + fromSeconds(6.0);
  for (auto& f : seq.frames) {
    if (f.t < slide_from) continue;
    const double px = toSeconds(f.t - slide_from) * 20.0;  // frames since the slide began
    for (auto& o : f.features)
      if (o.track_id % 10 == 0) o.normalized.x() += px / seq.focal_px;
  }
  EstimatorOptions keep, drop;
  drop.outlier_drops_landmark = true;
  const auto kept = runEstimator(seq, keep);
  const auto dropped = runEstimator(seq, drop);
  int outliers_kept = 0, outliers_dropped = 0;
  for (const auto& o : kept.outputs) outliers_kept += o.num_outliers;
  for (const auto& o : dropped.outputs) outliers_dropped += o.num_outliers;
  std::printf("sliding tracks: ATE %.4f m keeping their landmarks (%d outliers), %.4f m dropping them (%d)\n",
              kept.ate_m, outliers_kept, dropped.ate_m, outliers_dropped);
  EXPECT_EQ(dropped.resets, 0);
  EXPECT_LT(dropped.ate_m, 0.7 * kept.ate_m);
}

TEST(SlidingWindowEstimator, MovingStart) {
  SyntheticConfig cfg;
  cfg.duration_s = 10.0;
  cfg.still_s = -4.0;  // already moving when the recording starts
  const auto seq = generateSequence(cfg);
  const auto res = runEstimator(seq, EstimatorOptions{});
  ASSERT_GT(res.tracked_frames, 150);
  bool moving_init = false;
  for (const auto& o : res.outputs) moving_init |= o.message.find("moving start") != std::string::npos;
  EXPECT_TRUE(moving_init);
  EXPECT_EQ(res.resets, 0);
  EXPECT_LE(res.ate_m, 0.10);
  std::printf("moving start: ATE %.4f m over %d frames\n", res.ate_m, res.tracked_frames);
}

// Offline and live runs of the same input must give the same trajectory: nothing may depend on
// wall-clock time, machine load or what else the process has allocated (Ceres orders an
// elimination group's blocks by address, so frames and landmarks live in the estimator's pools).
TEST(SlidingWindowEstimator, DeterministicTrajectory) {
  SyntheticConfig cfg;
  cfg.duration_s = 8.0;
  const auto seq = generateSequence(cfg);
  const auto a = runEstimator(seq, EstimatorOptions{});
  std::vector<std::unique_ptr<char[]>> clutter;  // moves everything the second run allocates
  for (int i = 0; i < 333; ++i) clutter.emplace_back(new char[static_cast<std::size_t>(16 + 48 * (i % 7))]);
  const auto b = runEstimator(seq, EstimatorOptions{});
  ASSERT_EQ(a.outputs.size(), b.outputs.size());
  int compared = 0, differing = 0;
  for (std::size_t i = 0; i < a.outputs.size(); ++i) {
    ASSERT_EQ(a.outputs[i].frame_accepted, b.outputs[i].frame_accepted) << "frame " << i;
    ASSERT_EQ(a.outputs[i].is_keyframe, b.outputs[i].is_keyframe) << "frame " << i;
    if (!a.outputs[i].frame_accepted) continue;
    differing += a.outputs[i].p_WB != b.outputs[i].p_WB || a.outputs[i].q_WB.coeffs() != b.outputs[i].q_WB.coeffs() ||
                 a.outputs[i].pose_covariance != b.outputs[i].pose_covariance;
    ++compared;
  }
  EXPECT_GT(compared, 100);
  EXPECT_EQ(differing, 0) << "frames whose pose or covariance differ in any bit";
}

TEST(SlidingWindowEstimator, ZeroVelocityDetectedAtRest) {
  SyntheticConfig cfg;
  cfg.duration_s = 3.0;
  cfg.still_s = 10.0;  // at rest throughout
  cfg.pixel_noise_px = 0.2;
  const auto seq = generateSequence(cfg);
  const auto res = runEstimator(seq, EstimatorOptions{});
  int zero_velocity = 0;
  for (const auto& o : res.outputs) zero_velocity += o.zero_velocity ? 1 : 0;
  EXPECT_GT(zero_velocity, res.tracked_frames / 2);
  const auto& last = res.outputs.back();
  EXPECT_LT(last.v_WB.norm(), 0.01);
  EXPECT_LT(last.p_WB.norm(), 0.01);
}

// Feeds a sequence through the estimator with a hook that may alter each step.
struct Feeder {
  const SyntheticSequence& seq;
  SlidingWindowEstimator est;
  std::size_t k = 0;
  explicit Feeder(const SyntheticSequence& s, EstimatorOptions o = {})
      : seq(s), est(o, s.T_BC0, s.T_BC1, s.focal_px, s.noise) {}
  void imuUpTo(Timestamp t) {
    while (k < seq.imu.size() && seq.imu[k].t <= t) est.addImu(seq.imu[k++]);
  }
  EstimatorOutput frame(std::size_t i) {
    imuUpTo(seq.frames[i].t);
    return est.addFrame(seq.frames[i]);
  }
};

SyntheticSequence shortSequence() {
  SyntheticConfig cfg;
  cfg.duration_s = 5.0;
  cfg.still_s = 1.5;
  return generateSequence(cfg);
}

TEST(SlidingWindowEstimatorInput, BadImuSamplesAreSkipped) {
  const auto seq = shortSequence();
  Feeder f(seq);
  for (std::size_t i = 0; i < 40; ++i) f.frame(i);
  ImuSample nan_sample = seq.imu[f.k];
  nan_sample.accel.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(f.est.addImu(nan_sample));
  ImuSample inf_sample = seq.imu[f.k];
  inf_sample.gyro.z() = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(f.est.addImu(inf_sample));
  EXPECT_FALSE(f.est.addImu(seq.imu[f.k - 1]));  // duplicate time
  EXPECT_FALSE(f.est.addImu(seq.imu[f.k - 5]));  // backwards
  EstimatorOutput last;
  for (std::size_t i = 40; i < seq.frames.size(); ++i) last = f.frame(i);
  EXPECT_TRUE(last.frame_accepted);
  EXPECT_EQ(last.status, EstimatorStatus::kTracking);
  EXPECT_EQ(f.est.resetCount(), 0);
  EXPECT_LT((last.p_WB - seq.truth.back().p).norm(), 0.1);
}

TEST(SlidingWindowEstimatorInput, FrameWithoutFeaturesPropagatesWithImu) {
  const auto seq = shortSequence();
  Feeder f(seq);
  for (std::size_t i = 0; i < 50; ++i) f.frame(i);
  FeatureFrame empty = seq.frames[50];
  empty.features.clear();
  f.imuUpTo(empty.t);
  const auto out = f.est.addFrame(empty);
  EXPECT_TRUE(out.frame_accepted);
  EXPECT_EQ(out.status, EstimatorStatus::kTracking);
  EXPECT_NE(out.message.find("no features"), std::string::npos) << out.message;
  EXPECT_LT((out.p_WB - seq.truth[50].p).norm(), 0.1);
  EstimatorOutput last;
  for (std::size_t i = 51; i < seq.frames.size(); ++i) last = f.frame(i);
  EXPECT_EQ(last.status, EstimatorStatus::kTracking);
  EXPECT_LT((last.p_WB - seq.truth.back().p).norm(), 0.1);
}

TEST(SlidingWindowEstimatorInput, FrameBeforeItsImuIsSkippedThenTrackingContinues) {
  const auto seq = shortSequence();
  Feeder f(seq);
  for (std::size_t i = 0; i < 50; ++i) f.frame(i);
  // Frame 50 arrives before the IMU samples that reach its time.
  const auto early = f.est.addFrame(seq.frames[50]);
  EXPECT_FALSE(early.frame_accepted);
  EXPECT_NE(early.message.find("no IMU"), std::string::npos) << early.message;
  EstimatorOutput last;
  for (std::size_t i = 51; i < seq.frames.size(); ++i) last = f.frame(i);
  EXPECT_TRUE(last.frame_accepted);
  EXPECT_EQ(f.est.resetCount(), 0);
  EXPECT_LT((last.p_WB - seq.truth.back().p).norm(), 0.1);
}

TEST(SlidingWindowEstimatorInput, DuplicateAndBackwardsFramesAreRejected) {
  const auto seq = shortSequence();
  Feeder f(seq);
  for (std::size_t i = 0; i < 50; ++i) f.frame(i);
  const auto dup = f.est.addFrame(seq.frames[49]);
  EXPECT_FALSE(dup.frame_accepted);
  EXPECT_NE(dup.message.find("duplicate"), std::string::npos) << dup.message;
  const auto back = f.est.addFrame(seq.frames[30]);
  EXPECT_FALSE(back.frame_accepted);
  EXPECT_NE(back.message.find("older"), std::string::npos) << back.message;
  const auto next = f.frame(50);
  EXPECT_TRUE(next.frame_accepted);
  EXPECT_EQ(f.est.resetCount(), 0);
}

TEST(SlidingWindowEstimatorInput, NonFiniteFeaturesAreSkipped) {
  const auto seq = shortSequence();
  Feeder f(seq);
  for (std::size_t i = 0; i < 50; ++i) f.frame(i);
  FeatureFrame bad = seq.frames[50];
  for (std::size_t j = 0; j < bad.features.size(); j += 3) bad.features[j].normalized.x() = std::nan("");
  bad.features[1].camera_index = 7;
  f.imuUpTo(bad.t);
  const auto out = f.est.addFrame(bad);
  EXPECT_TRUE(out.frame_accepted);
  EXPECT_NE(out.message.find("non-finite"), std::string::npos) << out.message;
  EXPECT_TRUE(out.p_WB.allFinite());
  EXPECT_LT((out.p_WB - seq.truth[50].p).norm(), 0.1);
}

// A hole in the IMU stream larger than max_imu_gap_s resets the estimator with a message; the
// position continues from the last good estimate (no jump) and tracking resumes.
TEST(SlidingWindowEstimatorInput, ImuGapResetsWithoutJump) {
  const auto seq = shortSequence();
  Feeder f(seq);
  EstimatorOutput before;
  for (std::size_t i = 0; i < 60; ++i) before = f.frame(i);
  // Drop 0.3 s of IMU.
  while (f.k < seq.imu.size() && seq.imu[f.k].t < seq.frames[60].t + 300'000'000) ++f.k;
  EstimatorOutput out;
  std::size_t i = 61;
  for (; i < seq.frames.size(); ++i) {
    out = f.frame(i);
    if (out.status == EstimatorStatus::kReset) break;
  }
  ASSERT_EQ(out.status, EstimatorStatus::kReset);
  EXPECT_NE(out.message.find("IMU gap"), std::string::npos) << out.message;
  EXPECT_EQ(f.est.resetCount(), 1);
  EXPECT_TRUE(out.frame_accepted);
  EXPECT_LT((out.p_WB - before.p_WB).norm(), 0.05);
  EstimatorOutput last;
  for (++i; i < seq.frames.size(); ++i) last = f.frame(i);
  EXPECT_EQ(last.status, EstimatorStatus::kTracking);
  EXPECT_TRUE(last.frame_accepted);
}

// Corrupted accelerometer data (a 0.3 s burst of +80 m/s^2) must be caught as a failure (jump
// against the visual solution or implausible state) and reset, never crash or go non-finite.
TEST(SlidingWindowEstimatorInput, CorruptImuIsDetectedAndReset) {
  const auto seq = shortSequence();
  SyntheticSequence bad = seq;
  for (auto& s : bad.imu)
    if (s.t > seq.frames[60].t && s.t < seq.frames[66].t) s.accel.x() += 80.0;
  Feeder f(bad);
  bool reset_seen = false;
  EstimatorOutput last;
  for (std::size_t i = 0; i < bad.frames.size(); ++i) {
    last = f.frame(i);
    if (last.status == EstimatorStatus::kReset) {
      reset_seen = true;
      EXPECT_FALSE(last.message.empty());
    }
    if (last.frame_accepted) {
      EXPECT_TRUE(last.p_WB.allFinite());
    }
  }
  EXPECT_TRUE(reset_seen);
  EXPECT_GE(f.est.resetCount(), 1);
  EXPECT_EQ(last.status, EstimatorStatus::kTracking);
}

TEST(EstimatorOptions, LoadsFromYamlAndNamesBadKeys) {
  const YAML::Node ok = YAML::Load("imu_window_size: 7\nrobust_loss: cauchy\nobservation_sigma_px: 0.7\npixel_scale: local\n");
  const auto o = EstimatorOptions::fromYaml(ok, "test.yaml");
  EXPECT_EQ(o.imu_window_size, 7);
  EXPECT_EQ(o.pixel_scale, PixelScale::kLocal);
  EXPECT_EQ(o.robust_loss, RobustLoss::kCauchy);
  EXPECT_DOUBLE_EQ(o.observation_sigma_px, 0.7);
  EXPECT_EQ(o.keyframe_window_size, EstimatorOptions{}.keyframe_window_size);

  auto expectError = [](const std::string& yaml, const std::string& key) {
    try {
      EstimatorOptions::fromYaml(YAML::Load(yaml), "test.yaml");
      ADD_FAILURE() << "no error for " << yaml;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("test.yaml"), std::string::npos) << e.what();
    }
  };
  expectError("imu_window_size: 1\n", "imu_window_size");
  expectError("observation_sigma_px: -1\n", "observation_sigma_px");
  expectError("max_iterations: many\n", "max_iterations");
  expectError("robust_loss: tukey\n", "robust_loss");
  expectError("pixel_scale: center\n", "pixel_scale");
  expectError("imu_windw_size: 4\n", "imu_windw_size");
  expectError("conflict:\n  hold_moving_min_fraction: 0\n", "hold_moving_min_fraction");
  expectError("conflict:\n  frontend_agreement_ends_hold: maybe\n", "frontend_agreement_ends_hold");
  expectError("conflict:\n  frontend_min_count: 2\n", "frontend_min_count");
  expectError("conflict:\n  frontend_min_fraction: 1.5\n", "frontend_min_fraction");
  expectError("conflict:\n  frontend_marginal_score: 0.5\n", "frontend_marginal_score");
  expectError("conflict:\n  frontend_evidence: maybe\n", "frontend_evidence");
  expectError("conflict:\n  bias_drift_sigmas: -1\n", "bias_drift_sigmas");
  expectError("conflict:\n  split_chi2_threshold: -60\n", "split_chi2_threshold");
  expectError("conflict:\n  bias_drift_arm_frames: -5\n", "bias_drift_arm_frames");
  expectError("conflict:\n  bias_drift_min_frames: 0\n", "bias_drift_min_frames");

  const std::string path = ::testing::TempDir() + "/estimator_options_test.yaml";
  std::ofstream(path) << "estimator:\n  keyframe_window_size: 3\n";
  EXPECT_EQ(EstimatorOptions::fromYamlFile(path).keyframe_window_size, 3);
  EXPECT_THROW(EstimatorOptions::fromYamlFile(path + ".missing"), InputError);
}

// The shipped file lists every option with its default value.
TEST(EstimatorOptions, ShippedConfigEqualsDefaults) {
  const auto o = EstimatorOptions::fromYamlFile(std::string(MCVIO_ESTIMATOR_CONFIG_DIR) + "/estimator.yaml");
  const EstimatorOptions d;
  EXPECT_EQ(o.imu_window_size, d.imu_window_size);
  EXPECT_EQ(o.keyframe_window_size, d.keyframe_window_size);
  EXPECT_EQ(o.robust_loss, d.robust_loss);
  EXPECT_DOUBLE_EQ(o.function_tolerance, d.function_tolerance);
  EXPECT_DOUBLE_EQ(o.conflict_function_tolerance, d.conflict_function_tolerance);
  EXPECT_DOUBLE_EQ(o.outlier_threshold_px, d.outlier_threshold_px);
  EXPECT_EQ(o.outlier_drops_landmark, d.outlier_drops_landmark);
  EXPECT_EQ(o.pixel_scale, d.pixel_scale);
  EXPECT_DOUBLE_EQ(o.init_roll_pitch_sigma_moving, d.init_roll_pitch_sigma_moving);
  EXPECT_DOUBLE_EQ(o.max_time_without_vision_s, d.max_time_without_vision_s);
  EXPECT_EQ(o.right_camera_in_all_frames, d.right_camera_in_all_frames);
  EXPECT_EQ(o.marginalize_tracked_landmark_history, d.marginalize_tracked_landmark_history);
  const YAML::Node root = YAML::LoadFile(std::string(MCVIO_ESTIMATOR_CONFIG_DIR) + "/estimator.yaml");
  EXPECT_EQ(root.size(), 52u) << "every option appears once";
  // The conflict section lists every conflict option with its default.
  const auto& c = o.conflict;
  const conflict::ConflictOptions dc;
  EXPECT_EQ(c.mode, dc.mode);
  EXPECT_EQ(c.horizon_frames, dc.horizon_frames);
  EXPECT_DOUBLE_EQ(c.velocity_sigma_mps, dc.velocity_sigma_mps);
  EXPECT_DOUBLE_EQ(c.accel_bias_sigma, dc.accel_bias_sigma);
  EXPECT_DOUBLE_EQ(c.propagated_chi2_threshold, dc.propagated_chi2_threshold);
  EXPECT_DOUBLE_EQ(c.landmark_chi2_threshold, dc.landmark_chi2_threshold);
  EXPECT_DOUBLE_EQ(c.landmark_attitude_sigma_rad, dc.landmark_attitude_sigma_rad);
  EXPECT_EQ(c.auto_min_static_landmarks, dc.auto_min_static_landmarks);
  EXPECT_EQ(c.rewind_frames, dc.rewind_frames);
  EXPECT_EQ(c.exit_frames, dc.exit_frames);
  EXPECT_EQ(c.exit_quiet_frames, dc.exit_quiet_frames);
  EXPECT_DOUBLE_EQ(c.exit_quiet_score, dc.exit_quiet_score);
  EXPECT_EQ(c.new_landmark_probation, dc.new_landmark_probation);
  EXPECT_EQ(c.probation_agreeing_tests, dc.probation_agreeing_tests);
  EXPECT_EQ(c.exit_bias_hold_frames, dc.exit_bias_hold_frames);
  EXPECT_EQ(c.thin_view_bias_hold_landmarks, dc.thin_view_bias_hold_landmarks);
  EXPECT_EQ(c.thin_view_bias_hold_usable_tracks, dc.thin_view_bias_hold_usable_tracks);
  EXPECT_EQ(c.split_bias_hold, dc.split_bias_hold);
  EXPECT_EQ(c.frontend_conflict_keeps_history, dc.frontend_conflict_keeps_history);
  EXPECT_EQ(c.vision_depth_weighting, dc.vision_depth_weighting);
  EXPECT_DOUBLE_EQ(c.smoothing_held_acceleration_sigma, dc.smoothing_held_acceleration_sigma);
  EXPECT_EQ(c.frontend_labels_outside_min_count, dc.frontend_labels_outside_min_count);
  EXPECT_EQ(c.frontend_labels_after_conflict_frames, dc.frontend_labels_after_conflict_frames);
  EXPECT_EQ(c.partial_min_count, dc.partial_min_count);
  EXPECT_DOUBLE_EQ(c.partial_min_fraction, dc.partial_min_fraction);
  EXPECT_EQ(c.hold_moving_min_count, dc.hold_moving_min_count);
  EXPECT_DOUBLE_EQ(c.hold_moving_min_fraction, dc.hold_moving_min_fraction);
  EXPECT_EQ(c.frontend_agreement_ends_hold, dc.frontend_agreement_ends_hold);
  EXPECT_EQ(c.frontend_evidence, dc.frontend_evidence);
  EXPECT_EQ(c.frontend_min_count, dc.frontend_min_count);
  EXPECT_DOUBLE_EQ(c.frontend_min_fraction, dc.frontend_min_fraction);
  EXPECT_DOUBLE_EQ(c.frontend_marginal_score, dc.frontend_marginal_score);
  EXPECT_EQ(c.frontend_evidence_after_imu_exit, dc.frontend_evidence_after_imu_exit);
  EXPECT_DOUBLE_EQ(c.bias_drift_sigmas, dc.bias_drift_sigmas);
  EXPECT_EQ(c.bias_drift_arm_frames, dc.bias_drift_arm_frames);
  EXPECT_EQ(c.bias_drift_min_frames, dc.bias_drift_min_frames);
  EXPECT_DOUBLE_EQ(c.bias_drift_fast_factor, dc.bias_drift_fast_factor);
  EXPECT_EQ(c.bias_drift_fast_frames, dc.bias_drift_fast_frames);
  EXPECT_EQ(c.bias_drift_long_frames, dc.bias_drift_long_frames);
  EXPECT_DOUBLE_EQ(c.bias_drift_long_sigmas, dc.bias_drift_long_sigmas);
  EXPECT_DOUBLE_EQ(c.split_chi2_threshold, dc.split_chi2_threshold);
  EXPECT_EQ(c.split_min_frames, dc.split_min_frames);
  EXPECT_EQ(c.keep_consistent_rotation, dc.keep_consistent_rotation);
  EXPECT_DOUBLE_EQ(c.rotation_chi2_threshold, dc.rotation_chi2_threshold);
  EXPECT_EQ(c.exit_velocity_frames, dc.exit_velocity_frames);
  EXPECT_EQ(c.exit_velocity_frames_after_hold, dc.exit_velocity_frames_after_hold);
  EXPECT_EQ(c.smoothing_reidentified_min_landmarks, dc.smoothing_reidentified_min_landmarks);
  EXPECT_DOUBLE_EQ(c.smoothing_settled_velocity_sigma, dc.smoothing_settled_velocity_sigma);
  EXPECT_DOUBLE_EQ(c.smoothing_registration_radius_m, dc.smoothing_registration_radius_m);
  EXPECT_DOUBLE_EQ(c.smoothing_registration_tolerance_m, dc.smoothing_registration_tolerance_m);
  EXPECT_DOUBLE_EQ(c.smoothing_registration_min_fraction, dc.smoothing_registration_min_fraction);
  EXPECT_DOUBLE_EQ(c.smoothing_registration_max_ambiguity, dc.smoothing_registration_max_ambiguity);
  EXPECT_EQ(root["conflict"].size(), 80u) << "every conflict option appears once";
}

}  // namespace
}  // namespace mcvio::estimator
