#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/time.hpp"

namespace mcvio::sim {

/// Pose of the body (IMU) frame in the world with its time derivatives, all exact (analytic).
/// World: z up, gravity (0, 0, -9.81). Body frame = IMU frame, as in EuRoC.
struct KinematicState {
  Eigen::Vector3d p_wb = Eigen::Vector3d::Zero();      ///< position [m]
  Eigen::Quaterniond q_wb = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();       ///< velocity in the world frame [m/s]
  Eigen::Vector3d a_w = Eigen::Vector3d::Zero();       ///< acceleration in the world frame [m/s^2]
  Eigen::Vector3d omega_b = Eigen::Vector3d::Zero();   ///< angular rate in the body frame [rad/s]
};

/// A device trajectory: the body pose and its derivatives at any time inside [startTime, endTime].
class Trajectory {
 public:
  virtual ~Trajectory() = default;
  /// State at time t (nanoseconds, same clock as the output data set).
  virtual KinematicState evaluate(Timestamp t) const = 0;
  virtual Timestamp startTime() const = 0;
  virtual Timestamp endTime() const = 0;
};

}  // namespace mcvio::sim
