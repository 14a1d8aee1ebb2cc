#pragma once
#include <Eigen/Geometry>
#include <string>

#include "mcvio/core/camera_model.hpp"

namespace mcvio {

/// One camera's calibration, as in a EuRoC cam*/sensor.yaml.
/// The resolution lives in `model` (model.width(), model.height()).
struct CameraCalibration {
  std::string name = "cam0";
  CameraModel model;
  double rate_hz = 20.0;
  /// Camera -> body (IMU) frame: p_B = T_BC * p_C. This is EuRoC's T_BS of the camera.
  Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();
  /// The ROS topic the camera was calibrated on (Kalibr's rostopic, absolute), which a component
  /// reads in place of /camN/image_raw unless told otherwise; empty: not named (EuRoC).
  std::string topic;
};

}  // namespace mcvio
