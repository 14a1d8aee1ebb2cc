#pragma once
#include <string>
#include <vector>

#include "mcvio/core/stereo_rig_calibration.hpp"

namespace mcvio::dataset {

/// What `--calib PATH` names: a EuRoC folder (mav0/cam0, cam1, imu0 sensor.yaml; the folder
/// holding mav0/ or mav0/ itself), or Kalibr's files: a camchain-imucam YAML, or a folder holding
/// one camchain-imucam*.yaml, with the one imu*.yaml beside it (see KalibrCalibration).
/// Throws mcvio::InputError naming the path and what it lacks.
class RigCalibrationReader {
 public:
  /// `warnings` (if given) gets a line per sensor.yaml key a EuRoC folder has that is not read.
  static StereoRigCalibration read(const std::string& path, std::vector<std::string>* warnings = nullptr);
  /// True when `path` is read as a EuRoC folder (it holds mav0/ or cam0/), false for Kalibr's files.
  static bool isEurocFolder(const std::string& path);
};

}  // namespace mcvio::dataset
