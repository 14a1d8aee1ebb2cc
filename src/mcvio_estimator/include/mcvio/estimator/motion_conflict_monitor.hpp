#pragma once
#include <cstdint>
#include <deque>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/conflict/conflict_interval_tracker.hpp"
#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/conflict/landmark_conflict_detector.hpp"
#include "mcvio/conflict/landmark_motion_classifier.hpp"
#include "mcvio/conflict/propagated_state_detector.hpp"
#include "mcvio/conflict/region_split_detector.hpp"
#include "mcvio/conflict/relative_pose_solver.hpp"
#include "mcvio/conflict/secondary_motion_tracker.hpp"
#include "mcvio/core/imu_noise.hpp"
#include "mcvio/estimator/conflict_interval_smoother.hpp"
#include "mcvio/estimator/estimator_output.hpp"
#include "mcvio/estimator/imu_bias.hpp"
#include "mcvio/estimator/imu_buffer.hpp"

namespace mcvio::estimator {

/// The estimator's motion-conflict layer (dissertation ch. 5-6, DESIGN.md "The algorithm").
///
/// Before each solve it compares the body motion over the last `horizon_frames` as the IMU
/// predicts it (from the estimated state at the reference frame r) with what vision alone says
/// (stereo points of r re-observed in k): the propagated-state detector on the whole motion, the
/// landmark detector per landmark with a rigid-motion coherence test of the disagreeing group.
/// Hysteresis turns the evidence into intervals, and the mode decides the resolution the
/// estimator applies: IMU-dominated (no visual residuals, biases held, rewind to the state before
/// the evidence), selective (eliminate the landmarks whose verdict history says they move), or
/// auto. After the solve, commit() stores the frame and updates the conflicting frame's motion.
class MotionConflictMonitor {
 public:
  using ObservationMap = std::unordered_map<std::uint64_t, Eigen::Vector2d>;

  /// The estimated state of a frame.
  struct State {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    ImuBias bias;
  };

  /// What the estimator must do with the current frame.
  struct Decision {
    ConflictReport report;
    bool imu_dominated = false;      ///< no visual residuals, biases held at `held_bias`
    /// Just after an IMU-dominated interval: vision back, biases still held at `held_bias`.
    bool hold_bias = false;
    ImuBias held_bias;
    bool rewind = false;             ///< restart the window from `rewind_state` propagated to this frame
    State rewind_state;
    Timestamp rewind_t = 0;
    /// An IMU-dominated interval ended with a velocity jump: restart the window from `exit_state`
    /// (this frame's pose, vision's velocity, the held biases).
    bool restart_on_exit = false;
    State exit_state;
    double exit_velocity_jump_mps = 0;  ///< vision's velocity minus the inertial one, at the exit
    bool suppress_zero_velocity = false;  ///< vision at rest inside a moving frame says nothing
    std::vector<std::uint64_t> eliminate;  ///< tracks declared moving in this frame
    /// IMU-dominated with a rotation vision and gyro agree on: vision's rotation from the previous
    /// frame to this one (R_prev^T R_cur) with its square-root information.
    bool vision_rotation = false;
    Eigen::Quaterniond q_prev_cur = Eigen::Quaterniond::Identity();
    Eigen::Matrix3d rotation_sqrt_information = Eigen::Matrix3d::Identity();
  };

  /// The frontend's verdicts on one frame's cam0 tracks (FeatureFrame labels).
  struct FrontendVerdicts {
    std::unordered_set<std::uint64_t> inconsistent;  ///< labelled inconsistent
    std::unordered_set<std::uint64_t> consistent;    ///< labelled consistent
    int checked = 0;                                 ///< labelled consistent or inconsistent
  };

  MotionConflictMonitor(const conflict::ConflictOptions& options, const conflict::RigGeometry& rig,
                        const ImuNoiseParams& imu_noise, const Eigen::Vector3d& gravity, double min_depth_m,
                        double max_depth_m);

  /// Tests frame k (time t, its observations, the frontend's verdicts on its tracks).
  Decision process(Timestamp t, const ObservationMap& cam0, const ObservationMap& cam1,
                   const FrontendVerdicts& frontend, const ImuBuffer& imu);
  /// Stores frame k with its solved state (call after the solve, also in reference mode).
  void commit(const State& solved, ConflictReport* report);
  /// Forgets everything (after an estimator reset).
  void reset();

  bool isEliminated(std::uint64_t track_id) const { return classifier_.isMoving(track_id); }
  /// Selective resolution holds this landmark (created at `created`) out of the estimate: see
  /// ConflictOptions::new_landmark_probation.
  bool onProbation(std::uint64_t track_id, Timestamp created) const;
  bool imuDominated() const { return imu_dominated_; }
  /// A conflict is suspected or open (in any mode, reference included).
  bool conflictActive() const { return tracker_.state() != conflict::ConflictIntervalTracker::State::kNone; }
  /// A conflict is active and only the frontend's labels have found motion in it so far (see
  /// ConflictOptions::frontend_conflict_keeps_history).
  bool conflictFromFrontendOnly() const { return conflictActive() && !backend_found_motion_; }
  /// The track disagreed with the static world within the horizon (any test, or a frontend label).
  bool disagreedRecently(std::uint64_t track_id) const { return last_disagreed_.count(track_id) != 0; }
  /// Oldest time the monitor still needs IMU for (the conflict window's start while it is open).
  Timestamp oldestTimeNeeded() const;
  /// The conflict window after an IMU-dominated interval is ready to be smoothed (see
  /// ConflictIntervalSmoother), with the state committed last as its settled end.
  bool smoothingReady() const { return options_.smoothing_enabled && smoother_.ready(); }
  /// When the conflict window opened: its start state's time (the map remembered up to then
  /// is in the frame the window starts in).
  Timestamp smoothingStartTime() const { return smoother_.startTime(); }
  /// When the IMU-dominated interval of that window ended.
  Timestamp smoothingExitTime() const { return smoother_.exitTime(); }
  /// Smooths it against the last committed state (and the end position vision gives from
  /// re-identified landmarks, if any) and moves the stored states by the shift; with the
  /// covariance at the window's start, the result also has the shift's.
  ConflictIntervalSmoother::Result smoothInterval(const ImuBuffer& imu,
                                                  const ConflictIntervalSmoother::ReidentifiedEnd* reidentified = nullptr,
                                                  const ConflictIntervalSmoother::StartCovariance* start = nullptr);

 private:
  struct Entry {
    Timestamp t = 0;
    ObservationMap cam0, cam1;
    /// Stereo depth in cam0 of the tracks both cameras saw and triangulate() accepted: each frame
    /// is tested against two earlier ones and serves as the earlier one many times.
    std::unordered_map<std::uint64_t, double> depth;
    State state;
    bool evidence = false;
    Eigen::Isometry3d vision_increment = Eigen::Isometry3d::Identity();  ///< body k -> body k-1, vision only
    bool vision_increment_valid = false;
    Eigen::Matrix3d vision_rotation_covariance = Eigen::Matrix3d::Identity();
    bool secondary_valid = false;  ///< the conflicting frame's velocity at this frame
    Eigen::Vector3d v_WS = Eigen::Vector3d::Zero();
  };

  bool triangulate(const Eigen::Vector2d& n0, const Eigen::Vector2d& n1, double* depth) const;
  /// Tracks in view the estimate can use in a selective interval: not found moving, not on probation.
  int usableTracks(const ObservationMap& cam0) const;
  /// Fills e.depth from e.cam0 and e.cam1.
  void triangulateAll(Entry* e) const;
  /// The tracks of frame k (cam0 and the depths of k) that r saw in stereo, as r -> k points.
  std::vector<conflict::TrackedPoint> collectPoints(const Entry& r, const ObservationMap& cam0,
                                                    const Entry& k) const;
  /// IMU-predicted motion from r to t, integrated with the reference bias (see
  /// ConflictOptions::bias_reference_lag_frames); `propagated` is r's state moved to t. With
  /// `landmark_motion`, the same motion with the landmark detector's attitude uncertainty
  /// (ConflictOptions::landmark_attitude_sigma_rad).
  bool imuMotion(const Entry& r, Timestamp t, const ImuBuffer& imu, conflict::RelativeMotion* motion,
                 State* propagated, conflict::RelativeMotion* landmark_motion = nullptr) const;
  /// How many of the latest history frames (at most max_frames) still saw at least
  /// min_landmarks_tested of the tracks in cam0.
  std::size_t trackReach(const ObservationMap& cam0, std::size_t max_frames) const;
  /// Vision-only world velocity at history index i: the vision displacement over the `span` frames
  /// before it, with the IMU's preintegration over the same frames.
  bool visionVelocity(std::size_t i, std::size_t span, const ImuBuffer& imu, Eigen::Vector3d* v) const;
  /// Vision-only motion from `prev` to `cur` (from the tracks not found moving, or from all when
  /// those give none), stored in `cur`.
  void solveVisionIncrement(const Entry& prev, const ImuBuffer& imu, Entry* cur) const;
  /// Every bias estimated after history_[i] stayed close to it (bias_reference_max_change_sigmas).
  bool biasSettled(std::size_t i) const;
  ImuBias referenceBias(const Entry& r) const { return have_reference_bias_ ? reference_bias_ : r.state.bias; }

  conflict::ConflictOptions options_;
  conflict::RigGeometry rig_;
  Eigen::Isometry3d T_C1C0_, T_C0C1_;
  ImuNoiseParams imu_noise_;
  Eigen::Vector3d gravity_;
  double min_depth_, max_depth_;
  conflict::RelativePoseSolver pose_solver_;
  conflict::PropagatedStateDetector propagated_detector_;
  conflict::LandmarkConflictDetector landmark_detector_;
  conflict::RegionSplitDetector split_detector_;
  /// The region split's test found the group of the conflict suspected or open now. Auto then
  /// stays selective when most landmarks come to disagree with the IMU, as long as at least
  /// auto_min_static_landmarks tracks in view are not found moving: the IMU prediction starts from
  /// a state the object pulled before it was found (the rendered slow object, growing to 77 % of
  /// the view, went IMU-dominated mid-interval with a rewind into that pull: 0.046 -> 0.141 m; only
  /// while the split kept firing: 0.141 m too, it flaps once the moving tracks are eliminated). The
  /// count lets an elevator go IMU-dominated once its doors close (with the frontend's labels the
  /// cabin's tracks are all eliminated; held selective, the window lost every landmark: 11.6 m).
  bool split_group_seen_ = false;
  bool backend_found_motion_ = false;  ///< in the open interval: a landmark group, a held split, a whole-view run, or IMU-dominated
  int whole_run_ = 0;  ///< consecutive frames of the open interval with a whole-view test firing
  int split_run_ = 0;  ///< consecutive frames the split fired beside a side that agrees with the IMU
  int frontend_group_run_ = 0;  ///< consecutive frames with a labelled group (frontend_marginal_score)
  /// Frame index (frame_index_ counts process() calls in selective and auto) at which each track
  /// last disagreed (a landmark verdict, the test of moving tracks against the others' motion,
  /// the frontend's label), kept for horizon_frames frames or until the frontend finds it
  /// consistent (frontend_agreement_ends_hold).
  std::unordered_map<std::uint64_t, std::int64_t> last_disagreed_;
  std::int64_t frame_index_ = 0;
  /// When each track in view was first seen (selective and auto): a track first seen at or after
  /// active_since_ is on probation in the estimate until confirmed static.
  std::unordered_map<std::uint64_t, Timestamp> first_seen_;
  conflict::ConflictIntervalTracker tracker_;
  conflict::LandmarkMotionClassifier classifier_;
  conflict::SecondaryMotionTracker secondary_;

  std::deque<Entry> history_;
  Entry pending_;            ///< frame k between process() and commit()
  bool have_pending_ = false;
  bool imu_dominated_ = false;
  bool drift_opened_ = false;  ///< the bias-drift detector opened the IMU-dominated interval
  Eigen::Vector3d drift_direction_W_ = Eigen::Vector3d::Zero();  ///< of the bias bend that opened it, world frame
  bool entered_on_drift_ = false;  ///< the bias drift fired on the open interval's first frame
  bool speed_hold_engaged_ = false;  ///< the secondary speed has held the interval open
  bool speed_hold_holding_ = false;  ///< ... and did on the last frame
  int drift_frames_ = 0;             ///< consecutive frames with the bias drift over its limit
  int fast_drift_frames_ = 0;        ///< ... and over bias_drift_fast_factor times it
  int long_drift_frames_ = 0;        ///< consecutive frames with the slow drift (bias_drift_long_frames) over its limit
  ConflictIntervalSmoother smoother_;
  double evidence_secondary_speed_ = 0;  ///< fastest along the peak while the detectors had evidence
  Eigen::Vector3d peak_secondary_velocity_ = Eigen::Vector3d::Zero();  ///< fastest in this IMU-dominated interval
  ImuBias held_bias_;
  bool selective_bias_hold_ = false;  ///< a selective interval holds the biases: ConflictOptions::thin_view_bias_hold_*, split_bias_hold
  ImuBias selective_held_bias_;      ///< ... the bias it holds
  ImuBias reference_bias_;
  bool have_reference_bias_ = false;
  int frames_since_reset_ = 0;
  int frames_since_imu_exit_ = -1;  ///< -1: no IMU-dominated interval has ended since the last reset
  int frames_since_interval_ = -1;  ///< frames outside since the last interval closed; 0 inside one; -1: none yet
  int frames_after_conflict_ = -1;  ///< frames committed since the last one in conflict; -1: none yet
  Timestamp active_since_ = 0;      ///< the frame before the first of the current suspected or open conflict (probation from there)
};

}  // namespace mcvio::estimator
