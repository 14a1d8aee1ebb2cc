#pragma once
#include <string>
#include <vector>

#include "mcvio/core/camera_calibration.hpp"
#include "mcvio/core/imu_calibration.hpp"

namespace mcvio::dataset {

/// EuRoC/Kalibr `sensor.yaml` files of cameras and IMUs.
///
/// Camera keys: T_BS {rows: 4, cols: 4, data: [16 row-major]}, rate_hz, resolution [w, h],
/// camera_model (pinhole; optional), intrinsics [fu, fv, cu, cv],
/// distortion_model (radial-tangential | equidistant | none), distortion_coefficients [4].
/// IMU keys: T_BS, rate_hz, gyroscope_noise_density, gyroscope_random_walk,
/// accelerometer_noise_density, accelerometer_random_walk.
/// Errors throw mcvio::InputError naming the file and the key (and the line for syntax errors).
class SensorYaml {
 public:
  /// Reads a camera's sensor.yaml; `name` becomes CameraCalibration::name.
  static CameraCalibration readCamera(const std::string& path, const std::string& name);
  /// Reads an IMU's sensor.yaml; `name` becomes ImuCalibration::name.
  static ImuCalibration readImu(const std::string& path, const std::string& name);
  /// One warning per top-level key of the file at `path` that readCamera() (`camera` true) or
  /// readImu() does not read, naming the file, line and key: a misspelt optional key
  /// (`camera_modle: ds`) would otherwise be ignored without a word. Call after the read.
  static std::vector<std::string> unreadKeys(const std::string& path, bool camera);

  /// Writes the files in EuRoC's layout; every double is written with the shortest text that
  /// reads back to the same value. Throws mcvio::InputError if the file cannot be written.
  static void writeCamera(const std::string& path, const CameraCalibration& calibration);
  static void writeImu(const std::string& path, const ImuCalibration& calibration);
  /// Writes a sensor.yaml with only T_BS (as EuRoC's ground-truth folder has).
  static void writePoseSensor(const std::string& path, const std::string& sensor_type,
                              const std::string& comment, const Eigen::Isometry3d& T_BS);
};

}  // namespace mcvio::dataset
