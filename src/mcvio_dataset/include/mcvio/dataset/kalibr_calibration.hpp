#pragma once
#include <string>

#include "mcvio/core/stereo_rig_calibration.hpp"

namespace mcvio::dataset {

/// Kalibr's calibration files, as OpenVINS, VINS and Basalt users have them.
///
/// camchain-imucam.yaml (kalibr_calibrate_imu_camera's output): cam0 and cam1, each with
/// camera_model (pinhole), intrinsics [fu, fv, pu, pv], distortion_model (radtan, equidistant,
/// none), distortion_coeffs, resolution [w, h], T_cam_imu (4 rows of 4: IMU -> camera) and
/// timeshift_cam_imu (t_imu = t_cam + shift, seconds). cam1 may give T_cn_cnm1 (cam0 -> cam1)
/// instead of T_cam_imu; with both they must agree. Other cameras, rostopic and cam_overlaps are
/// not used. The IMU is the body frame, as in EuRoC.
///
/// The IMU file: Kalibr's imu.yaml (accelerometer_noise_density, accelerometer_random_walk,
/// gyroscope_noise_density, gyroscope_random_walk, update_rate), or its results file with those
/// keys under imu0.
///
/// Errors throw mcvio::InputError naming the file, the camera and the key.
class KalibrCalibration {
 public:
  static StereoRigCalibration read(const std::string& camchain_path, const std::string& imu_path);
};

}  // namespace mcvio::dataset
