#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/imu_noise.hpp"
#include "mcvio/core/time.hpp"
#include "mcvio/estimator/estimator_output.hpp"
#include "mcvio/estimator/imu_bias.hpp"
#include "mcvio/estimator/imu_buffer.hpp"

namespace mcvio::estimator {

class ImuPreintegrator;

/// The conflict window of the triple-window optimisation (dissertation ch. 6). Inside an
/// IMU-dominated interval the position comes from the IMU alone with the biases held at their
/// pre-conflict estimate, so an error of that estimate, or of the attitude that removes gravity,
/// grows into a velocity error, then a position error. Once the interval has ended and vision has
/// re-established the velocity, the interval is re-estimated from its start state: the IMU is
/// integrated over every frame (with the estimator's orientations, which vision kept) with one
/// acceleration correction in the world frame, fitted so that the inertial velocity after the exit
/// equals the visual one. Its direction is fixed over the window, its size is not: the true
/// accelerometer bias keeps walking while the held one stays, so given the velocity error at the
/// end T the expected error at time t grows as sigma0^2 + q (t - t^2 / 2T) (sigma0 the held
/// estimate's error, q the random walk's variance rate; constant for q = 0). (A correction of the
/// accelerometer bias in the body frame fitted the same velocities worse: 0.50 against 0.21 m ATE
/// on the feature-level elevator, 0.64 against 0.45 m on the rendered one.) The result is the
/// corrected position of each frame, the conflicting frame's poses moved with them, and the shift
/// that brings the live window onto the corrected end. When the map seen before the interval is
/// seen again after it (MapMemory), vision also gives the end position in the window's starting
/// frame; then the correction gets a second term, a ramp over the window, and is fitted to the
/// velocities and that position together (three numbers more for an interval the IMU alone
/// carried).
class ConflictIntervalSmoother {
 public:
  struct Options {
    /// Frames after the interval ends before the smoothing runs: vision needs them to correct
    /// the velocity the interval carried out.
    int settle_frames = 20;
    /// A larger correction [m/s^2] means the end velocity is not the world's (the interval
    /// closed while the conflicting frame still moved): nothing is changed.
    double max_acceleration_correction = 0.2;
    /// A window longer than this [s] is given up (one correction cannot describe it, and the IMU
    /// kept for it would grow without bound).
    double max_window_s = 120.0;
    /// How far the held accelerometer bias and the gravity removal may be off when the window
    /// opens [m/s^2, per axis]. Against the accelerometer random walk it sets the correction's
    /// shape over time: large values make it constant.
    double held_acceleration_sigma = 0.01;
    /// How far a settled velocity may be off [m/s per axis]; weighs the velocities against a
    /// re-identified end position.
    double settled_velocity_sigma = 0.02;
  };

  struct Result {
    bool applied = false;
    std::string message;                                          ///< why not, or what was done
    /// World frame, at its largest (the end of the window) [m/s^2].
    Eigen::Vector3d acceleration_correction = Eigen::Vector3d::Zero();
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();  ///< corrected minus estimated position at the end [m]
    std::vector<EstimatorOutput::PoseRevision> revisions;  ///< every frame after the start, the last one included
    /// The conflicting frame's pose at every frame that published one (setSecondary), moved by
    /// the body's revision at that frame: S is measured from the body.
    std::vector<EstimatorOutput::PoseRevision> secondary_revisions;
    bool used_reidentified = false;  ///< the re-identified end position was fitted
    /// Covariance of the corrected end position's error [m^2], valid when finish() was given
    /// the start's covariance: what the start's attitude, velocity and bias errors, the IMU's
    /// noise over the window and the settled velocities' error leave after the fit (first
    /// order). The live window's covariance knows none of it: the correction is not a solve.
    Eigen::Matrix3d shift_covariance = Eigen::Matrix3d::Zero();
    bool shift_covariance_valid = false;
  };

  /// The estimator's marginal covariance at the state the window opens at, over [attitude error
  /// in the world frame, velocity, gyroscope bias, accelerometer bias] (body-frame biases).
  using StartCovariance = Eigen::Matrix<double, 12, 12>;

  explicit ConflictIntervalSmoother(const Options& options) : options_(options) {}

  /// Opens the window at the last state before the conflict (the biases are the held ones).
  void begin(Timestamp t0, const Eigen::Vector3d& p0, const Eigen::Quaterniond& q0, const Eigen::Vector3d& v0,
             const ImuBias& bias);
  /// A frame of the interval (or after it, while settling) with its estimated orientation; past
  /// max_window_s the window closes unsmoothed.
  void addFrame(Timestamp t, const Eigen::Quaterniond& q);
  /// The conflicting frame's pose published at the last added frame t, with the body position
  /// published there; ignored if t is not that frame.
  void setSecondary(Timestamp t, const Eigen::Vector3d& p_WB, const Eigen::Vector3d& p_WS,
                    const Eigen::Quaterniond& q_WS);
  /// The IMU-dominated interval ended at the last added frame.
  void markExit();
  /// A new IMU-dominated interval opened before the smoothing ran: the window goes on.
  void resumeInterval() { exited_ = false; }
  void cancel() { active_ = false; }

  bool active() const { return active_; }
  bool exited() const { return active_ && exited_; }
  /// Exited, and settle_frames frames have been added since.
  bool ready() const;
  Timestamp startTime() const { return t0_; }
  /// The last frame of the IMU-dominated interval (the start time before the exit).
  Timestamp exitTime() const { return exit_index_ > 0 && exit_index_ <= frames_.size() ? frames_[exit_index_ - 1].t : t0_; }

  /// The estimator's velocity at a frame after the exit (vision back in charge).
  struct SettledVelocity {
    Timestamp t = 0;
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
  };
  /// The last added frame's position in the frame the window started in, from landmarks seen
  /// before the interval and re-identified after it.
  struct ReidentifiedEnd {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    double sigma = 0.05;  ///< [m per axis]
    int landmarks = 0;
  };
  /// Re-estimates the window. `settled` are the estimator's velocities at frames after the exit
  /// (the correction fits them all, in the least-squares sense: one visual velocity is too noisy
  /// for an interval of many seconds); `p_end` is its position at the last added frame. With
  /// `reidentified` the end position is fitted too, unless it lies further from the velocity-only
  /// fit than a held bias error of three held_acceleration_sigma explains (then the
  /// re-identified landmarks moved: an elevator's cabin seen again after the ride). With `start`
  /// (the covariance at the window's start) the result also says how far the corrected end may
  /// be off. Closes the window whatever the outcome.
  Result finish(const ImuBuffer& imu, const ImuNoiseParams& noise, const Eigen::Vector3d& gravity,
                const Eigen::Vector3d& p_end, const std::vector<SettledVelocity>& settled,
                const ReidentifiedEnd* reidentified = nullptr, const StartCovariance* start = nullptr);

 private:
  struct Node {
    Timestamp t = 0;
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    bool has_secondary = false;
    Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();  ///< as published with the secondary pose
    Eigen::Vector3d p_WS = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q_WS = Eigen::Quaterniond::Identity();
  };
  /// First-order error of the inertial propagation, carried frame by frame as a covariance over
  /// [attitude, velocity, position, gyro bias, accel bias (as in ImuPreintegrator), and the sum
  /// over the settled frames of Jv^T times the velocity error (9)]: the fit is linear in that sum.
  using ErrorCovariance = Eigen::Matrix<double, 24, 24>;
  static void propagateError(const Eigen::Matrix3d& R, const ImuPreintegrator& pre, ErrorCovariance* P);
  static void accumulateSettledError(const Eigen::Matrix<double, 3, 9>& Jv, ErrorCovariance* P);

  Options options_;
  bool active_ = false, exited_ = false;
  Timestamp t0_ = 0;
  Eigen::Vector3d p0_ = Eigen::Vector3d::Zero(), v0_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q0_ = Eigen::Quaterniond::Identity();
  ImuBias bias_;
  std::vector<Node> frames_;
  std::size_t exit_index_ = 0;  ///< frames_.size() when the interval ended
};

}  // namespace mcvio::estimator
