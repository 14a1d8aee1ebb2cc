#pragma once
#include <Eigen/Core>

#include "mcvio/core/time.hpp"

namespace mcvio {

/// One IMU reading in the body (imu0) frame: angular rate [rad/s] and specific force [m/s^2].
struct ImuSample {
  Timestamp t = 0;
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
};

}  // namespace mcvio
