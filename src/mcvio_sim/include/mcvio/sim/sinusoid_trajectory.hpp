#pragma once
#include <vector>

#include "mcvio/sim/trajectory.hpp"

namespace mcvio::sim {

/// One term A * sin(2*pi*f*t + phase) of a smooth periodic signal.
struct SinusoidTerm {
  double amplitude = 0.0;     ///< [m] or [rad]
  double frequency_hz = 0.0;
  double phase = 0.0;         ///< [rad]
};

/// A smooth hand-held / MAV-like 6-DoF trajectory with exact derivatives: each position axis and
/// each Euler angle (yaw-pitch-roll, z-y-x) is a sum of sinusoids; yaw may also turn at a constant
/// rate so the device looks ahead along a loop. The position never leaves center +- sum|amplitude|.
class SinusoidTrajectory : public Trajectory {
 public:
  struct Options {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    std::vector<SinusoidTerm> x, y, z;  ///< position terms per world axis
    double yaw0 = 0.0;                  ///< heading of the camera's optical axis at t = 0 [rad]
    double yaw_rate = 0.0;              ///< constant turn rate [rad/s]
    std::vector<SinusoidTerm> yaw, pitch, roll;

    /// A loop through a box of half extents `half` (x, y, z) taking `period_s` per lap, with the
    /// camera looking roughly along the direction of travel and small hand-like oscillations.
    /// `look_outward` turns the view that many radians towards the outside of the loop.
    static Options loop(const Eigen::Vector3d& center, const Eigen::Vector3d& half, double period_s,
                        double look_outward = 0.35);
    /// Hand-held motion in place: small translations inside `half`, a slow turn at `yaw_rate`.
    static Options handHeld(const Eigen::Vector3d& center, const Eigen::Vector3d& half,
                            double yaw_rate);
  };

  SinusoidTrajectory(Options options, Timestamp start, Timestamp end);

  KinematicState evaluate(Timestamp t) const override;
  Timestamp startTime() const override { return start_; }
  Timestamp endTime() const override { return end_; }

  /// Largest excursion from `center` per axis (sum of the absolute amplitudes).
  Eigen::Vector3d maxExcursion() const;
  const Options& options() const { return options_; }

 private:
  Options options_;
  Timestamp start_;
  Timestamp end_;
};

/// Rotation from the body (IMU) frame to a "look" frame (x forward, y left, z up) for the EuRoC
/// rig, whose cameras look along body +z with image-right along body +y.
Eigen::Matrix3d lookFromBodyRotation();

}  // namespace mcvio::sim
