// End-to-end regression of motion-conflict detection and resolution on short feature-level
// scenarios (mcvio_sim FeatureSimulator, seeded): the estimator in each mode against the
// reference VIO on the same input.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "mcvio/estimator/sliding_window_estimator.hpp"
#include "mcvio/evaluation/ate.hpp"
#include "mcvio/sim/feature_simulator.hpp"

using namespace mcvio;

namespace {

struct ScenarioRun {
  double ate = 0;                   ///< position+yaw aligned RMSE [m]
  int frames = 0, labelled = 0, detected = 0, detected_labelled = 0, false_alarms = 0;
  int resets = 0;
  double ride_truth = 0, ride_estimate = 0, secondary_rise = 0;  ///< vertical change over the labelled interval [m]
  double final_secondary_rise = 0;  ///< the same for the cabin once the conflict window revised it [m]
  bool bias_held_in_conflict = true;  ///< IMU-dominated frames all carry the same biases
  int imu_dominated_frames = 0;
  int invalid_covariance = 0;  ///< tracked frames whose pose covariance was singular or not finite
  double max_position_sigma = 0;  ///< largest position standard deviation reported [m]
  /// Position NEES (aligned at the first pose) of the frames after the conflict window was
  /// smoothed: mean, and the frames it averages.
  double nees_after_smoothing = 0;
  int frames_after_smoothing = 0;
};

sim::FeatureSequence makeSequence(sim::ScenarioKind kind, double duration_s, double onset_s, double conflict_s,
                                  std::uint64_t seed, double travel_m = 0.0) {
  sim::SimulatorOptions so;
  so.duration_s = duration_s;
  so.seed = seed;
  so.scenario.kind = kind;
  so.scenario.onset_s = onset_s;
  so.scenario.duration_s = conflict_s;
  so.scenario.travel_m = travel_m;  // 0: the scenario's default
  return sim::simulateFeatureSequence(so, sim::FeatureSimulatorOptions{});
}

/// As mcvio bench runs the feature level: no oracle track labels (a real frontend cannot know them).
sim::FeatureSequence withoutTrackLabels(sim::FeatureSequence seq) {
  for (auto& f : seq.frames)
    for (auto& o : f.features) o.label = TrackLabel::kUnknown;
  return seq;
}

ScenarioRun run(const sim::FeatureSequence& seq, conflict::ResolutionMode mode,
               const conflict::ConflictOptions& conflict_options = conflict::ConflictOptions{}) {
  estimator::EstimatorOptions eo;
  eo.observation_sigma_px = sim::FeatureSimulatorOptions{}.pixel_noise_sigma;
  eo.conflict = conflict_options;
  eo.conflict.mode = mode;
  estimator::SlidingWindowEstimator est(eo, seq.calibration);
  ScenarioRun r;
  evaluation::Trajectory e, g;
  std::size_t k = 0, gi = 0, li = 0;
  bool in_ride = false;
  double z_truth0 = 0, z_est0 = 0;
  Timestamp last_labelled_t = 0;
  std::vector<estimator::EstimatorOutput::PoseRevision> secondary;  // as published, then revised
  estimator::ImuBias held;
  bool have_held = false;
  bool aligned = false, smoothed = false;
  Eigen::Isometry3d T_align = Eigen::Isometry3d::Identity();  // estimate -> truth at the first pose
  for (const auto& f : seq.frames) {
    while (k < seq.imu.size() && seq.imu[k].t <= f.t) est.addImu(seq.imu[k++]);
    const auto out = est.addFrame(f);
    if (!out.frame_accepted || out.status != estimator::EstimatorStatus::kTracking) continue;
    while (gi + 1 < seq.ground_truth.size() && seq.ground_truth[gi].t < f.t) ++gi;
    while (li + 1 < seq.labels.size() && seq.labels[li].t < f.t) ++li;
    if (seq.ground_truth[gi].t != f.t) continue;
    const bool label = seq.labels[li].t == f.t && seq.labels[li].in_conflict;
    const bool detected = out.conflict.state == estimator::ConflictReport::State::kConflict;
    ++r.frames;
    r.labelled += label;
    r.detected += detected;
    r.detected_labelled += detected && label;
    r.false_alarms += detected && !label;
    if (!out.covariance_valid) {
      ++r.invalid_covariance;
    } else {
      r.max_position_sigma =
          std::max(r.max_position_sigma, std::sqrt(out.pose_covariance.topLeftCorner<3, 3>().diagonal().maxCoeff()));
    }
    e.append({f.t, out.p_WB, out.q_WB});
    g.append({f.t, seq.ground_truth[gi].p_WB, seq.ground_truth[gi].q_WB});
    if (!aligned) {
      const auto iso = [](const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = q.toRotationMatrix();
        T.translation() = p;
        return T;
      };
      T_align = iso(seq.ground_truth[gi].p_WB, seq.ground_truth[gi].q_WB) * iso(out.p_WB, out.q_WB).inverse();
      aligned = true;
    }
    smoothed = smoothed || !out.revised_poses.empty();
    if (smoothed && out.covariance_valid) {
      const Eigen::Vector3d err = seq.ground_truth[gi].p_WB - T_align * out.p_WB;
      const Eigen::Matrix3d cov = T_align.linear() * out.pose_covariance.topLeftCorner<3, 3>() * T_align.linear().transpose();
      r.nees_after_smoothing += err.dot(cov.ldlt().solve(err));
      ++r.frames_after_smoothing;
    }
    if (label) {
      if (!in_ride) {
        in_ride = true;
        z_truth0 = seq.ground_truth[gi].p_WB.z();
        z_est0 = out.p_WB.z();
      }
      r.ride_truth = seq.ground_truth[gi].p_WB.z() - z_truth0;
      r.ride_estimate = out.p_WB.z() - z_est0;
      last_labelled_t = f.t;
    }
    const bool imu_dominated = out.conflict.resolution_mode == "imu" || out.conflict.resolution_mode == "auto:imu";
    if (detected && imu_dominated) {
      ++r.imu_dominated_frames;
      if (have_held && ((out.bias.accel - held.accel).norm() > 1e-9 || (out.bias.gyro - held.gyro).norm() > 1e-9))
        r.bias_held_in_conflict = false;
      held = out.bias;
      have_held = true;
    } else {
      have_held = false;
    }
    if (out.conflict.secondary_valid) {
      r.secondary_rise = out.conflict.p_WS.z();
      secondary.push_back({f.t, out.conflict.p_WS, out.conflict.q_WS});
    }
    estimator::applyPoseRevisions(&secondary, out.revised_secondary);
  }
  for (const auto& s : secondary)
    if (s.t <= last_labelled_t) r.final_secondary_rise = s.p_WB.z();  // the cabin starts at identity
  if (r.frames_after_smoothing > 0) r.nees_after_smoothing /= r.frames_after_smoothing;
  r.resets = est.resetCount();
  r.ate = evaluation::computeAte(e, g, evaluation::Alignment::kPositionYaw).translation.rmse;
  return r;
}

}  // namespace

// A 12 m elevator ride: the camera sees only the cabin. The reference VIO follows the cabin; the
// IMU-dominated resolution keeps the inertial motion, and the ride's height.
TEST(MotionConflict, ElevatorRideImuDominatedCutsTheError) {
  const auto seq = makeSequence(sim::ScenarioKind::kElevator, 40.0, 12.0, 14.0, 3);
  const auto ref = run(seq, conflict::ResolutionMode::kReference);
  const auto imu = run(seq, conflict::ResolutionMode::kImu);
  const auto aut = run(seq, conflict::ResolutionMode::kAuto);
  std::printf("elevator: ATE reference %.3f m, imu %.3f m, auto %.3f m; ride truth %.2f m, imu %.2f m, auto %.2f m, "
              "secondary %.2f m (auto: %.2f m per frame, %.2f m revised); detected %d/%d labelled, %d false alarms\n",
              ref.ate, imu.ate, aut.ate, imu.ride_truth, imu.ride_estimate, aut.ride_estimate, imu.secondary_rise,
              aut.secondary_rise, aut.final_secondary_rise, imu.detected_labelled, imu.labelled, imu.false_alarms);
  std::printf("elevator covariance: invalid frames imu %d/%d, auto %d/%d; largest position sigma imu %.2f m, auto %.2f m; "
              "position NEES after the conflict window, imu %.2f over %d frames, auto %.2f over %d\n",
              imu.invalid_covariance, imu.frames, aut.invalid_covariance, aut.frames, imu.max_position_sigma,
              aut.max_position_sigma, imu.nees_after_smoothing, imu.frames_after_smoothing, aut.nees_after_smoothing,
              aut.frames_after_smoothing);
  ASSERT_GT(imu.labelled, 200);
  EXPECT_GT(ref.ate, 1.0);  // the conflict is real: the reference loses metres
  EXPECT_LT(imu.ate, 0.5 * ref.ate);
  EXPECT_LT(aut.ate, 0.5 * ref.ate);
  EXPECT_NEAR(imu.ride_estimate, imu.ride_truth, 0.1 * std::abs(imu.ride_truth));
  // The cabin's own motion (the target: within 10 % of the ride).
  EXPECT_NEAR(aut.final_secondary_rise, aut.ride_truth, 0.1 * std::abs(aut.ride_truth));
  EXPECT_GT(imu.detected_labelled, imu.labelled / 2);
  EXPECT_GT(imu.imu_dominated_frames, 50);
  EXPECT_TRUE(imu.bias_held_in_conflict);
  EXPECT_EQ(imu.resets, 0);
  // Fourteen seconds on the IMU alone: the covariance grows (metres) but stays a covariance. A
  // gauge lost to rounding made it singular on 20 frames and 5 km wide on another.
  EXPECT_EQ(imu.invalid_covariance, 0);
  EXPECT_EQ(aut.invalid_covariance, 0);
  EXPECT_LT(imu.max_position_sigma, 30.0);
  EXPECT_LT(aut.max_position_sigma, 30.0);
  // After the conflict window moved the window, the published covariance covers the error (2.7;
  // 27 when the correction had no uncertainty of its own and the restart at the exit a 1 cm one).
  EXPECT_GT(aut.frames_after_smoothing, 100);
  EXPECT_LT(aut.nees_after_smoothing, 8.0);
}

// A 24 m ride over 30 s (mcvio bench's duration sweep): the cabin eases in at under 0.05 m/s^2 for
// its first 1.3 s and peaks at 0.17 m/s^2, the horizon's tests stay quiet, and the estimator bends
// its accelerometer bias instead: without the bias-drift detector the ride is missed. It finds
// the ride about 3 s in, and its acceleration hold keeps the interval open until the cabin is fast
// enough for the speed hold.
TEST(MotionConflict, AGentleLongRideIsFoundByTheBiasDrift) {
  const auto seq = withoutTrackLabels(makeSequence(sim::ScenarioKind::kElevator, 65.0, 20.0, 30.0, 1, 24.0));
  const auto ref = run(seq, conflict::ResolutionMode::kReference);
  const auto aut = run(seq, conflict::ResolutionMode::kAuto);
  conflict::ConflictOptions no_drift;
  no_drift.bias_drift_sigmas = 0;
  const auto late = run(seq, conflict::ResolutionMode::kAuto, no_drift);
  std::printf("gentle 30 s ride: ATE reference %.3f m, auto %.3f m (without the bias-drift detector %.3f m); "
              "detected %d/%d labelled, %d false alarms\n",
              ref.ate, aut.ate, late.ate, aut.detected_labelled, aut.labelled, aut.false_alarms);
  ASSERT_GT(aut.labelled, 550);
  EXPECT_GT(ref.ate, 5.0);
  EXPECT_LT(aut.ate, 0.5 * ref.ate);
  EXPECT_GT(late.ate, 2.0 * aut.ate);
  EXPECT_GT(aut.detected_labelled, aut.labelled * 3 / 4);
  EXPECT_LE(aut.false_alarms, aut.frames / 50);
  EXPECT_EQ(aut.resets, 0);
}

// A laptop carried 0.3 m in front of the cameras covers most of the view for 12 s.
TEST(MotionConflict, SelfOcclusionAutoCutsTheError) {
  const auto seq = makeSequence(sim::ScenarioKind::kSelfOcclusion, 40.0, 12.0, 12.0, 4);
  const auto ref = run(seq, conflict::ResolutionMode::kReference);
  const auto aut = run(seq, conflict::ResolutionMode::kAuto);
  std::printf("self-occlusion: ATE reference %.3f m, auto %.3f m; detected %d/%d labelled, %d false alarms\n", ref.ate,
              aut.ate, aut.detected_labelled, aut.labelled, aut.false_alarms);
  std::printf("self-occlusion covariance: invalid frames auto %d/%d, largest position sigma %.2f m\n",
              aut.invalid_covariance, aut.frames, aut.max_position_sigma);
  EXPECT_LT(aut.ate, 0.5 * ref.ate);
  EXPECT_GT(aut.detected_labelled, aut.labelled * 3 / 4);
  EXPECT_EQ(aut.resets, 0);
  // Landmarks on the occluder keep a single inlier observation: their Schur complement made the
  // window's information indefinite on 12 frames.
  EXPECT_EQ(aut.invalid_covariance, 0);
  EXPECT_LT(aut.max_position_sigma, 30.0);
}

// mcvio bench's self-occlusion seed 3 (60 s, 15 s from 20 s, no oracle labels). When the laptop
// goes every track is new; the test inside the IMU-dominated interval took r's velocity from the
// H frames before r, which still saw the laptop, and the interval stayed open 2 H + exit_frames
// frames after it had gone: 24 false alarm frames, ATE of the online estimates 0.616 m. With the
// velocity and test spans cut to what the revealed tracks reach: 12 frames, 0.544 m (reference
// 2.223 m; mcvio bench, which scores the smoothed trajectory: 0.490 -> 0.415 m).
TEST(MotionConflict, TheIntervalOfAnOccluderThatHasGoneClosesOnTheRevealedTracks) {
  const auto seq = withoutTrackLabels(makeSequence(sim::ScenarioKind::kSelfOcclusion, 60.0, 20.0, 15.0, 3));
  const auto ref = run(seq, conflict::ResolutionMode::kReference);
  const auto aut = run(seq, conflict::ResolutionMode::kAuto);
  std::printf("self-occlusion seed 3: ATE reference %.3f m, auto %.3f m; detected %d/%d labelled, %d false alarms\n",
              ref.ate, aut.ate, aut.detected_labelled, aut.labelled, aut.false_alarms);
  ASSERT_GT(aut.labelled, 250);
  EXPECT_GT(aut.detected_labelled, aut.labelled * 9 / 10);
  EXPECT_LE(aut.false_alarms, 18);
  EXPECT_LT(aut.ate, 0.3 * ref.ate);
  EXPECT_EQ(aut.resets, 0);
}

// A slow object (about 0.08 m/s) drifts across half the view: each of its tracks moves by less
// than the IMU test's spread, and before the region-split detector the reference's pull went
// unnoticed for seconds (auto then went IMU-dominated late). Its static side's motion finds the
// object's landmarks, and selective elimination keeps the rest.
TEST(MotionConflict, ASlowObjectIsFoundByTheRegionSplit) {
  const auto seq = withoutTrackLabels(makeSequence(sim::ScenarioKind::kSlowObject, 40.0, 12.0, 14.0, 1));
  const auto ref = run(seq, conflict::ResolutionMode::kReference);
  const auto aut = run(seq, conflict::ResolutionMode::kAuto);
  conflict::ConflictOptions no_split;
  no_split.split_chi2_threshold = 0;
  const auto without = run(seq, conflict::ResolutionMode::kAuto, no_split);
  std::printf("slow object: ATE reference %.3f m, auto %.3f m (without the region split %.3f m); detected %d/%d "
              "labelled, %d false alarms\n",
              ref.ate, aut.ate, without.ate, aut.detected_labelled, aut.labelled, aut.false_alarms);
  ASSERT_GT(aut.labelled, 100);
  EXPECT_GT(ref.ate, 0.15);
  // Measured: reference 0.236 m, auto 0.072 m, without the split 0.234 m.
  EXPECT_LT(aut.ate, 0.4 * ref.ate);
  EXPECT_GT(without.ate, 2.0 * aut.ate);
  EXPECT_EQ(aut.false_alarms, 0);
  EXPECT_EQ(aut.resets, 0);
}

// A pedestrian crosses the view: selective elimination keeps the static landmarks.
TEST(MotionConflict, PedestrianSelectiveKeepsAccuracy) {
  const auto seq = makeSequence(sim::ScenarioKind::kPedestrian, 40.0, 12.0, 14.0, 5);
  const auto ref = run(seq, conflict::ResolutionMode::kReference);
  const auto sel = run(seq, conflict::ResolutionMode::kSelective);
  std::printf("pedestrian: ATE reference %.3f m, selective %.3f m; detected %d/%d labelled, %d false alarms\n", ref.ate,
              sel.ate, sel.detected_labelled, sel.labelled, sel.false_alarms);
  EXPECT_LE(sel.ate, ref.ate * 1.05 + 0.005);
  EXPECT_EQ(sel.imu_dominated_frames, 0);
  EXPECT_GT(sel.detected_labelled, 0);
}

// A clean sequence: no conflict may be reported for more than 2 % of the frames, and auto must
// not cost accuracy.
TEST(MotionConflict, CleanSequenceHasNoFalseConflicts) {
  const auto seq = makeSequence(sim::ScenarioKind::kNone, 40.0, 12.0, 12.0, 6);
  const auto ref = run(seq, conflict::ResolutionMode::kReference);
  const auto aut = run(seq, conflict::ResolutionMode::kAuto);
  std::printf("clean: ATE reference %.4f m, auto %.4f m; conflict frames %d/%d; invalid covariance %d, largest sigma %.3f m\n",
              ref.ate, aut.ate, aut.detected, aut.frames, aut.invalid_covariance, aut.max_position_sigma);
  ASSERT_GT(aut.frames, 700);
  EXPECT_LE(aut.detected, aut.frames / 50);
  EXPECT_LE(aut.ate, ref.ate * 1.05 + 0.001);
  EXPECT_EQ(aut.invalid_covariance, 0);
}
