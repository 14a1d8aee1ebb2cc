#pragma once
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/time.hpp"
#include "mcvio/estimator/imu_bias.hpp"

namespace mcvio::estimator {

/// Where the estimator stands after a frame.
enum class EstimatorStatus : std::uint8_t {
  kNotInitialized = 0,  ///< waiting for IMU history or a usable first frame; no pose yet
  kTracking = 1,        ///< normal operation
  kReset = 2,           ///< a failure was detected in this frame; the state was re-initialised
};

const char* toString(EstimatorStatus status);

/// Wall-clock cost of one frame, by stage [ms].
struct EstimatorTimings {
  double preintegration_ms = 0;
  double conflict_ms = 0;        ///< motion-conflict detectors and resolution bookkeeping
  double setup_ms = 0;           ///< landmark bookkeeping and building the Ceres problem
  double solve_ms = 0;
  double marginalization_ms = 0;
  double covariance_ms = 0;
  double total_ms = 0;           ///< wall clock of addFrame()
  double cpu_total_ms = 0;       ///< CPU time of the calling thread in addFrame()
};

/// Per-frame motion-conflict statistics (published as mcvio_msgs/MotionConflict, written to
/// OUT/conflict.csv). Filled in every mode; only the resolution depends on the mode.
struct ConflictReport {
  enum class State : std::uint8_t { kNone = 0, kSuspected = 1, kConflict = 2 };
  State state = State::kNone;
  double propagated_chi2 = 0;       ///< IMU-propagated vs vision-only relative pose, 6 dof
  double propagated_threshold = 0;
  int landmarks_tested = 0;         ///< landmark detector: tracks checked under the IMU prediction
  int landmarks_inconsistent = 0;
  double inconsistent_fraction = 0;
  double coherence = 0;             ///< share of the disagreeing group that one rigid motion explains
  Timestamp interval_start = 0;     ///< start of the current or last conflict interval; 0 if none
  /// The same interval in hindsight [m-, m+]: where its evidence began to build up, and (once it has
  /// closed; 0 while open) its last frame with evidence. See ConflictIntervalTracker.
  Timestamp interval_onset = 0;
  Timestamp interval_end = 0;
  std::string resolution_mode = "reference";  ///< the mode that acted on this frame
  int frontend_checked = 0;       ///< frontend detector: cam0 tracks the frontend labelled,
  int frontend_inconsistent = 0;  ///< and those it labelled inconsistent
  /// Bias-drift detector: newest accelerometer bias minus the reference bias [m/s^2]; 0 untested.
  double accel_bias_drift = 0;
  /// Region-split detector: largest chi-square between two image sides' vision-only motions; 0
  /// untested.
  double split_chi2 = 0;
  /// The frame's evidence score: the detector statistics relative to their thresholds, the largest
  /// of them (at least 1 on a frame with evidence). NaN before the warm-up ends or where nothing
  /// could be tested. The interval's onset in hindsight is where it built up (ConflictIntervalTracker).
  double evidence_score = std::numeric_limits<double>::quiet_NaN();
  /// The conflicting group's frame S (cabin, vehicle, carried object) in the world: identity at
  /// the interval start, then its rigid motion; valid only while a coherent group is tracked.
  bool secondary_valid = false;
  Eigen::Vector3d p_WS = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_WS = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_WS = Eigen::Vector3d::Zero();
};

const char* toString(ConflictReport::State state);

/// The estimator's answer for one frame.
struct EstimatorOutput {
  Timestamp t = 0;
  std::uint32_t frame_index = 0;
  EstimatorStatus status = EstimatorStatus::kNotInitialized;
  /// False when the frame was rejected (bad input or waiting for IMU); the state was not updated
  /// and the pose fields hold the last estimate (if any). `message` says why.
  bool frame_accepted = false;

  Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_WB = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_WB = Eigen::Vector3d::Zero();
  ImuBias bias;
  /// Covariance of [dp (world frame), dtheta (body frame, q = q_hat * Exp(dtheta))].
  Eigen::Matrix<double, 6, 6> pose_covariance = Eigen::Matrix<double, 6, 6>::Zero();
  bool covariance_valid = false;

  bool is_keyframe = false;
  bool zero_velocity = false;       ///< the frame was detected at rest
  int num_frames = 0;               ///< frames in the window (IMU window + keyframes)
  int num_keyframes = 0;
  int num_landmarks = 0;            ///< landmarks in the optimisation
  int num_visual_residuals = 0;     ///< reprojection residuals in the optimisation
  int num_tracked_features = 0;     ///< this frame's cam0 features that belong to a landmark
  int num_new_landmarks = 0;
  int num_outliers = 0;             ///< observations dropped after the solve
  int solver_iterations = 0;
  EstimatorTimings timings;
  ConflictReport conflict;
  /// Earlier frames re-estimated in this frame (the conflict window smoothed after an
  /// IMU-dominated interval; the last entry is this frame): position and orientation of imu0 in
  /// world. Empty on most frames.
  struct PoseRevision {
    Timestamp t = 0;
    Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q_WB = Eigen::Quaterniond::Identity();
  };
  std::vector<PoseRevision> revised_poses;
  /// The conflicting frame's poses (ConflictReport::p_WS, q_WS) published at those frames,
  /// moved with the body's revision (S is measured from the body). Empty on most frames.
  std::vector<PoseRevision> revised_secondary;
  std::string message;              ///< warnings about this frame's input, reset reasons
};

/// Replaces the poses that `revisions` re-estimated in a time-sorted sequence of stamped poses
/// (elements with `t`, assignable from {t, p, q}, e.g. a published path). Stamps not in the
/// sequence are skipped. Returns whether any pose changed.
template <class SortedPoses>
bool applyPoseRevisions(SortedPoses* poses, const std::vector<EstimatorOutput::PoseRevision>& revisions) {
  bool revised = false;
  for (const auto& rev : revisions) {
    const auto it = std::lower_bound(poses->begin(), poses->end(), rev.t,
                                     [](const auto& pose, Timestamp t) { return pose.t < t; });
    if (it == poses->end() || it->t != rev.t) continue;
    *it = {rev.t, rev.p_WB, rev.q_WB.normalized()};
    revised = true;
  }
  return revised;
}

}  // namespace mcvio::estimator
