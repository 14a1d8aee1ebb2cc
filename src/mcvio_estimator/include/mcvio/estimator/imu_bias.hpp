#pragma once
#include <Eigen/Core>

namespace mcvio::estimator {

/// Gyroscope and accelerometer biases [rad/s], [m/s^2], both in the body (IMU) frame.
struct ImuBias {
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
};

}  // namespace mcvio::estimator
