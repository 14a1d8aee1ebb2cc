#pragma once
#include <Eigen/Geometry>

#include "mcvio/core/camera_calibration.hpp"
#include "mcvio/core/imu_calibration.hpp"
#include "mcvio/core/time.hpp"

namespace mcvio {

/// Calibration of a stereo visual-inertial rig: two cameras and an IMU, all extrinsics
/// expressed in the common body frame B.
struct StereoRigCalibration {
  CameraCalibration cam0;  ///< left camera
  CameraCalibration cam1;  ///< right camera
  ImuCalibration imu;
  /// IMU time of a camera stamp minus the stamp [ns] (Kalibr's timeshift_cam_imu: t_imu = t_cam +
  /// shift); the frontend moves every frame by it. EuRoC folders have none (0).
  Timestamp camera_time_offset_ns = 0;

  /// cam1 -> cam0: p_C0 = T_C0C1 * p_C1 (derived from the two T_BC).
  Eigen::Isometry3d T_C0C1() const { return cam0.T_BC.inverse() * cam1.T_BC; }
  /// Stereo baseline [m]: distance between the two optical centres.
  double baseline() const { return (cam1.T_BC.translation() - cam0.T_BC.translation()).norm(); }
  /// Camera by index: 0 -> cam0, otherwise cam1.
  const CameraCalibration& camera(int index) const { return index == 0 ? cam0 : cam1; }
  CameraCalibration& camera(int index) { return index == 0 ? cam0 : cam1; }
};

}  // namespace mcvio
