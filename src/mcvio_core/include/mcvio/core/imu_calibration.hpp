#pragma once
#include <Eigen/Geometry>
#include <string>

#include "mcvio/core/imu_noise.hpp"

namespace mcvio {

/// The IMU's calibration, as in a EuRoC imu0/sensor.yaml (the rate is noise.rate_hz).
struct ImuCalibration {
  std::string name = "imu0";
  ImuNoiseParams noise;
  /// IMU sensor -> body frame: p_B = T_BS * p_S (identity in EuRoC, where the IMU is the body).
  Eigen::Isometry3d T_BS = Eigen::Isometry3d::Identity();
  /// The ROS topic the IMU was calibrated on (Kalibr's rostopic, absolute), read in place of
  /// /imu0 unless told otherwise; empty: not named (EuRoC).
  std::string topic;
};

}  // namespace mcvio
