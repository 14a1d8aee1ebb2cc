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

/// The conflict window of the triple-window optimisation (dissertation ch. 6). Inside an
/// IMU-dominated interval the position comes from the IMU alone with the biases held at their
/// pre-conflict estimate, so an error of that estimate, or of the attitude that removes gravity,
/// grows into a velocity error, then a position error. Once the interval has ended and vision has
/// re-established the velocity, the interval is re-estimated from its start state: the IMU is
/// integrated over every frame (with the estimator's attitudes; over the frames the estimator
/// rewound, with the gyro, as the rewind did), and the velocity errors after the exit are
/// explained by a model of the acceleration error: a tilt that leaks gravity sideways (an offset
/// when the window opens, growing at a rate as the held gyro bias turns the attitude), the held
/// accelerometer bias's error in the body frame, and that bias's random walk since. The
/// correction is the error's conditional mean given those velocities, so each source gets the
/// share its measured prior gives it. The result is the corrected position of each frame, the
/// conflicting frame's poses moved with them, and the shift that brings the live window onto the
/// corrected end.
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
    /// The held accelerometer bias's error when the window opens [m/s^2, per axis, body frame].
    /// Against the accelerometer random walk it sets how the correction grows over the window.
    double held_acceleration_sigma = 0.011;
    /// The horizontal gravity leak of the attitude's tilt error when the window opens [m/s^2, per
    /// axis, world frame], and how fast it grows inside the window [m/s^3].
    double tilt_acceleration_sigma = 0.0103;
    double tilt_acceleration_rate_sigma = 0.00155;
    /// Error of the settled velocities, all of them together [m/s].
    double velocity_sigma = 0.01;
  };

  struct Result {
    bool applied = false;
    std::string message;                                          ///< why not, or what was done
    /// World frame, at the last frame of the window [m/s^2].
    Eigen::Vector3d acceleration_correction = Eigen::Vector3d::Zero();
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();  ///< corrected minus estimated position at the end [m]
    std::vector<EstimatorOutput::PoseRevision> revisions;  ///< every frame after the start, the last one included
    /// The conflicting frame's pose at every frame that published one (setSecondary), moved by
    /// the body's revision at that frame: S is measured from the body.
    std::vector<EstimatorOutput::PoseRevision> secondary_revisions;
  };

  explicit ConflictIntervalSmoother(const Options& options) : options_(options) {}

  /// Opens the window at the last state before the conflict (the biases are the held ones).
  void begin(Timestamp t0, const Eigen::Vector3d& p0, const Eigen::Quaterniond& q0, const Eigen::Vector3d& v0,
             const ImuBias& bias);
  /// A frame of the interval (or after it, while settling) with its estimated orientation; past
  /// max_window_s the window closes unsmoothed. `rewound`: a frame between the window's start and
  /// the detection, whose orientation the conflict had pulled (the gyro's is used).
  void addFrame(Timestamp t, const Eigen::Quaterniond& q, bool rewound = false);
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

  /// The estimator's velocity at a frame after the exit (vision back in charge).
  struct SettledVelocity {
    Timestamp t = 0;
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
  };
  /// Re-estimates the window. `settled` are the estimator's velocities at frames after the exit
  /// (the correction fits them all, in the least-squares sense: one visual velocity is too noisy
  /// for an interval of many seconds); `p_end` is its position at the last added frame. Closes
  /// the window whatever the outcome.
  Result finish(const ImuBuffer& imu, const ImuNoiseParams& noise, const Eigen::Vector3d& gravity,
                const Eigen::Vector3d& p_end, const std::vector<SettledVelocity>& settled);

 private:
  struct Node {
    Timestamp t = 0;
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    bool rewound = false;  ///< the attitude comes from the gyro (see addFrame)
    bool has_secondary = false;
    Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();  ///< as published with the secondary pose
    Eigen::Vector3d p_WS = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q_WS = Eigen::Quaterniond::Identity();
  };
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
