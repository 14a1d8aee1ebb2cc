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
/// instead of T_cam_imu; with both they must agree. rostopic (optional) gives CameraCalibration::topic.
/// Other cameras and cam_overlaps are not used. The IMU is the body frame, as in EuRoC.
///
/// The IMU file: Kalibr's imu.yaml (accelerometer_noise_density, accelerometer_random_walk,
/// gyroscope_noise_density, gyroscope_random_walk, update_rate, optional rostopic), or its results
/// file with those keys under imu0.
///
/// Errors throw mcvio::InputError naming the file, the camera and the key.
class KalibrCalibration {
 public:
  static StereoRigCalibration read(const std::string& camchain_path, const std::string& imu_path);
  /// Writes `rig` as Kalibr's files, DIR/camchain-imucam.yaml and DIR/imu.yaml (DIR is created), as
  /// OpenVINS takes them: T_cam_imu for both cameras, T_cn_cnm1 for cam1, timeshift_cam_imu, and
  /// rostopic (the rig's topics, or /cam0/image_raw, /cam1/image_raw and /imu0). read() gives the
  /// rig back (the transforms to rounding). Throws mcvio::InputError if DIR cannot be written.
  static void write(const StereoRigCalibration& rig, const std::string& dir);
};

}  // namespace mcvio::dataset
