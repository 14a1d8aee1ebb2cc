#pragma once
#include <array>
#include <optional>
#include <deque>
#include <initializer_list>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/feature_frame.hpp"
#include "mcvio/core/imu_noise.hpp"
#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/estimator/estimator_options.hpp"
#include "mcvio/estimator/estimator_output.hpp"
#include "mcvio/estimator/imu_buffer.hpp"
#include "mcvio/estimator/imu_preintegrator.hpp"
#include "mcvio/estimator/map_memory.hpp"
#include "mcvio/estimator/marginalization_prior.hpp"
#include "mcvio/estimator/motion_conflict_monitor.hpp"
#include "mcvio/estimator/parameter_block_pool.hpp"
#include "mcvio/estimator/pose_manifold.hpp"

namespace ceres {
class LossFunction;
class CostFunction;
class Manifold;
}  // namespace ceres

namespace mcvio::estimator {

/// Reference keyframe stereo VIO backend (dissertation ch. 3, OKVIS-like).
///
/// Feed IMU samples with addImu() and feature frames with addFrame(), in time order; addFrame()
/// needs IMU up to the frame's time. Each frame gets a state (p, q, v, bg, ba); landmarks are
/// anchored inverse-depth points [alpha, beta, rho] in the cam0 frame of their first stereo
/// observation (the anchor). Ceres optimises a double
/// window: the newest N frames with full state linked by preintegrated IMU factors, and up to M
/// older keyframes with pose only. A frame leaving the IMU window keeps its pose if it is a
/// keyframe (its speed and biases are marginalised), otherwise it is marginalised with its IMU
/// link; a keyframe leaving its window is marginalised with the landmarks only it and other
/// keyframes see. Marginalisation is a Schur-complement prior (see Marginalizer).
///
/// Bad input never throws: it is skipped with a message in the output (and a log line), and a
/// detected failure resets the estimator to the last good position and yaw with status kReset.
class SlidingWindowEstimator {
 public:
  /// @param T_BC0, T_BC1 camera -> body (EuRoC T_BS of each camera).
  /// @param focal_length_px scales normalised-coordinate residuals to pixels.
  SlidingWindowEstimator(const EstimatorOptions& options, const Eigen::Isometry3d& T_BC0,
                         const Eigen::Isometry3d& T_BC1, double focal_length_px, const ImuNoiseParams& imu_noise);
  /// Takes extrinsics, focal length (cam0's at the centre), camera models (for
  /// EstimatorOptions::pixel_scale) and IMU noise from a rig calibration.
  SlidingWindowEstimator(const EstimatorOptions& options, const StereoRigCalibration& rig);
  ~SlidingWindowEstimator();
  SlidingWindowEstimator(const SlidingWindowEstimator&) = delete;
  SlidingWindowEstimator& operator=(const SlidingWindowEstimator&) = delete;

  /// Adds an IMU sample. Non-finite, duplicated or backwards samples are skipped with a warning;
  /// returns false for those.
  bool addImu(const ImuSample& sample);

  /// Processes one feature frame and returns the estimate at its time.
  EstimatorOutput addFrame(const FeatureFrame& frame);

  /// Drops the whole state (keeps IMU history and the last good position/yaw for re-initialisation).
  void reset(const std::string& reason);

  EstimatorStatus status() const { return initialized_ ? EstimatorStatus::kTracking : EstimatorStatus::kNotInitialized; }
  const EstimatorOptions& options() const { return options_; }
  /// World positions of the landmarks currently in the window.
  std::vector<Eigen::Vector3d> landmarkPositions() const;
  /// Number of resets so far.
  int resetCount() const { return reset_count_; }

 private:
  struct Frame {
    std::uint64_t id = 0;
    Timestamp t = 0;
    std::uint32_t frame_index = 0;
    std::array<double, 7> pose{};  ///< p, q (x, y, z, w)
    std::array<double, 9> sb{};    ///< v, bg, ba
    bool keyframe = false;
    bool has_speed_bias = true;    ///< in the IMU window
    bool zero_velocity = false;
    bool bias_held = false;        ///< inside an IMU-dominated conflict: biases fixed at the held value
    /// Vision's rotation from frame `rotation_prev_id` to this one, kept inside an IMU-dominated
    /// conflict while it agrees with the gyro.
    bool has_vision_rotation = false;
    std::uint64_t rotation_prev_id = 0;
    Eigen::Quaterniond vision_rotation = Eigen::Quaterniond::Identity();
    Eigen::Matrix3d vision_rotation_sqrt_info = Eigen::Matrix3d::Identity();
    std::unique_ptr<ImuPreintegrator> imu;  ///< from the previous frame, while both are in the IMU window
    std::unique_ptr<ceres::CostFunction> imu_cost;  ///< factor made from `imu`; reset whenever `imu` changes
    std::unordered_map<std::uint64_t, Eigen::Vector2d> cam0, cam1;  ///< track -> normalised coords
  };
  struct Landmark {
    std::uint64_t track_id = 0;
    std::uint64_t anchor_frame = 0;
    Timestamp created = 0;  ///< time of the frame that created it
    /// [alpha, beta, rho]: the point in the anchor frame's cam0 is (alpha, beta, 1) / rho. Lives
    /// in landmark_params_ at `slot`.
    double* param = nullptr;
    std::uint32_t slot = 0;
    double depth() const { return 1.0 / param[2]; }
  };
  /// Frames live in frame_storage_ (one array, see ParameterBlockPool for why addresses matter)
  /// and go back to it when released; beyond its size they come from the heap.
  struct FrameRecycler {
    SlidingWindowEstimator* owner = nullptr;
    void operator()(Frame* frame) const;
  };
  using FramePtr = std::unique_ptr<Frame, FrameRecycler>;
  enum class ResidualKind { kImu, kPrior, kZeroVelocity, kVisual, kVisionRotation };
  struct ResidualRecord {
    ResidualRecord(ceres::CostFunction* cost_function, ceres::LossFunction* loss_function,
                   std::initializer_list<double*> blocks, ResidualKind residual_kind);
    /// A prior: any number of blocks.
    ResidualRecord(ceres::CostFunction* cost_function, const std::vector<double*>& blocks);
    double* const* params() const { return num_params <= kInlineParams ? inline_params.data() : prior_params.data(); }

    static constexpr int kInlineParams = 4;
    ceres::CostFunction* cost;
    ceres::LossFunction* loss;
    ResidualKind kind;
    std::uint64_t track_id = 0;
    std::uint64_t frame_id = 0;
    int camera = 0;
    bool valid = true;
    int num_params = 0;
    // Blocks inline: a heap vector per residual and frame showed up in the allocator's profile.
    std::array<double*, kInlineParams> inline_params{};
    std::vector<double*> prior_params;
  };
  /// A visual cost function kept across frames: observation, camera and extrinsics do not change.
  struct ObservationCost {
    std::uint64_t frame_id = 0;
    int camera = 0;
    bool in_anchor = false;  ///< AnchorObservationFactor, else ReprojectionFactor
    bool used = false;       ///< in the current problem
    std::unique_ptr<ceres::CostFunction> cost;
  };

  FramePtr makeFrame();
  /// Gives a new landmark its parameter block.
  void placeLandmark(Landmark& lm);
  void clearLandmarks();
  bool initialize(FramePtr frame, std::string* message);
  Frame* frameById(std::uint64_t id);
  Frame& newest() { return *frames_.back(); }
  void createLandmarks(Frame& frame, int* created);
  bool triangulateStereo(const Eigen::Vector2d& n0, const Eigen::Vector2d& n1, double* depth) const;
  bool decideKeyframe(const Frame& frame) const;
  bool detectZeroVelocity(const Frame& prev, const Frame& cur) const;
  void repropagateImu();
  void solve(EstimatorOutput* out);
  void removeOutliers(EstimatorOutput* out);
  std::string checkFailure(const Eigen::Vector3d& p_pred) const;
  /// Restarts the window from a single frame with the given state and prior sigmas (position,
  /// world attitude, velocity, gyro and accel biases): the rewind at the start of an
  /// IMU-dominated interval and the restart at its end.
  /// `position_covariance`, if given, is where the covariance (whole_prior_) puts the position
  /// instead: the solver's anchor is a tuning sigma, the covariance keeps what was known.
  void restartFrom(Frame& cur, const MotionConflictMonitor::State& state, const Eigen::Matrix<double, 15, 1>& sigmas,
                   const Eigen::Matrix3d* position_covariance = nullptr);
  void setStatePrior(Frame& frame, const Eigen::Matrix<double, 15, 1>& sigmas);
  /// The covariance (whole_prior_, never the solver's prior) puts the window's common position at
  /// `covariance` and keeps its shape: after a restart or the conflict window's correction.
  void setWindowPositionCovariance(const Eigen::Matrix3d& covariance);
  void applyConflictDecision(const MotionConflictMonitor::Decision& decision, Frame& cur);
  /// The conflict window after an IMU-dominated interval: re-estimates it and moves the window.
  void smoothConflictWindow(EstimatorOutput* out);
  void commitToMonitor(EstimatorOutput* out);
  void computeCovariance(EstimatorOutput* out);
  void marginalize();
  void marginalizeOldestImuFrame();
  void marginalizeOldestKeyframe();
  void marginalizeWith(const std::vector<const ResidualRecord*>& records, const std::set<const double*>& drop);
  /// A conflict is suspected or open and the mode resolves it (not `reference`, the plain VIO).
  bool resolvingConflict() const;
  /// marginalize_tracked_landmark_history may put this landmark's history into the prior now: not
  /// while a conflict is resolved, unless ConflictOptions::frontend_conflict_keeps_history allows it.
  bool historyMayGoOn(std::uint64_t track_id) const;
  /// The first frame other than `leaving_frame` (with speed/biases if `imu_window_only`) that sees
  /// `lm`, and the landmark's parameters anchored there; false if none, or if the point is outside
  /// the depth range there.
  bool newAnchor(const Landmark& lm, std::uint64_t leaving_frame, bool imu_window_only, std::uint64_t* frame_id,
                 Eigen::Vector3d* param) const;
  /// Moves `lm` to its newAnchor, its estimate unchanged.
  bool reanchor(Landmark& lm, std::uint64_t leaving_frame, bool imu_window_only = false);
  void eraseLandmark(std::uint64_t track_id);
  /// Keeps a landmark leaving the window in map_memory_ (not while a conflict is suspected or
  /// open, nor one the conflict classifier holds moving), stamped `t`.
  void rememberLandmark(std::uint64_t track_id, Timestamp t);
  /// The end position vision gives in the conflict window's starting frame, from the window's
  /// landmarks that map_memory_ held before the window opened; false if too few agree.
  bool reidentifiedEnd(const Eigen::Vector3d& p_end, ConflictIntervalSmoother::ReidentifiedEnd* end) const;
  bool landmarkPointWorld(const Landmark& lm, Eigen::Vector3d* p_W) const;
  void fillState(EstimatorOutput* out) const;

  EstimatorOptions options_;
  Eigen::Isometry3d T_BC0_, T_BC1_, T_C1C0_;
  double focal_px_;
  /// The rig's lenses, when constructed from its calibration (for EstimatorOptions::pixel_scale).
  std::optional<std::array<CameraModel, 2>> cameras_;
  /// The lens's 2x2 pixel Jacobian at `normalised` in camera `camera`, where
  /// EstimatorOptions::pixel_scale asks for the local scale and the lenses are known; nullopt
  /// for the isotropic focal_px_.
  std::optional<Eigen::Matrix2d> localPixelJacobian(int camera, const Eigen::Vector2d& normalised) const;
  ImuNoiseParams imu_noise_;  ///< inflated
  Eigen::Vector3d gravity_;
  PoseManifold pose_manifold_;
  std::unique_ptr<ceres::LossFunction> loss_;
  std::unique_ptr<ceres::Manifold> bias_hold_manifold_;  ///< velocity free, biases constant
  std::unique_ptr<MotionConflictMonitor> monitor_;

  ImuBuffer imu_;
  std::vector<Frame> frame_storage_;  ///< declared before frames_: released frames return here
  std::vector<Frame*> free_frames_;
  std::deque<FramePtr> frames_;
  ParameterBlockPool landmark_params_{3};
  std::unordered_map<std::uint64_t, Landmark> landmarks_;
  MapMemory map_memory_;
  std::shared_ptr<MarginalizationPrior> prior_;
  /// All the information marginalisation has left (Marginalizer::SplitPrior::whole), of which
  /// prior_ keeps the strong directions: the covariance uses it in place of prior_, the solver
  /// never sees it. Same blocks as prior_, or null (then prior_ is the whole information).
  std::shared_ptr<MarginalizationPrior> whole_prior_;
  /// The newest frame's covariance over [position, attitude in the world, velocity, gyro bias,
  /// accel bias], per frame, back to the monitor's oldest time needed: where a conflict window
  /// starts, the smoother and the covariance after a restart need it.
  using StateCovariance = Eigen::Matrix<double, 15, 15>;
  std::deque<std::pair<Timestamp, StateCovariance>> state_covariances_;
  /// The latest of state_covariances_ at or before t; null if none.
  const StateCovariance* stateCovarianceAt(Timestamp t) const;
  std::vector<ResidualRecord> records_;  ///< residuals of the last solve
  /// Cost functions of records_ made for one solve, and priors made after it (visual ones live in
  /// observation_costs_, IMU ones in their frame).
  std::vector<std::unique_ptr<ceres::CostFunction>> extra_costs_;
  /// Visual cost functions by track; an entry lives while its observation is in the problem.
  std::unordered_map<std::uint64_t, std::vector<ObservationCost>> observation_costs_;
  struct ProblemHolder;
  std::unique_ptr<ProblemHolder> problem_;

  bool initialized_ = false;
  std::uint64_t next_frame_id_ = 0;
  Timestamp last_frame_t_ = 0;
  bool have_last_frame_t_ = false;
  Timestamp last_vision_t_ = 0;
  Timestamp settled_t_ = 0;  ///< from here on the solve may stop after the first step that meets its model
  Eigen::Vector3d last_good_p_ = Eigen::Vector3d::Zero();
  double last_good_yaw_ = 0;
  EstimatorOutput last_output_;
  int reset_count_ = 0;
};

}  // namespace mcvio::estimator
