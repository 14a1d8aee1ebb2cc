#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/time.hpp"

namespace mcvio::dataset {

/// One row of EuRoC's state_groundtruth_estimate0/data.csv: the body (IMU) frame B in the world
/// frame W, its velocity and the IMU biases.
struct GroundTruthState {
  Timestamp t = 0;
  Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();            ///< position [m]
  Eigen::Quaterniond q_WB = Eigen::Quaterniond::Identity();  ///< orientation (w first in the CSV)
  Eigen::Vector3d v_WB = Eigen::Vector3d::Zero();            ///< velocity in W [m/s]
  Eigen::Vector3d bias_gyro = Eigen::Vector3d::Zero();       ///< [rad/s]
  Eigen::Vector3d bias_accel = Eigen::Vector3d::Zero();      ///< [m/s^2]
};

}  // namespace mcvio::dataset
