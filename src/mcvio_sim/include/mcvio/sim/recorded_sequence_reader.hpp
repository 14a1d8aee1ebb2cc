#pragma once
#include <string>
#include <vector>

#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"

namespace mcvio::sim {

/// Reads the recorded inputs of semi-real simulation and image injection: EuRoC ground-truth
/// and IMU CSV files and a calibration folder. Errors throw mcvio::InputError naming the file
/// and line (or key).
class RecordedSequenceReader {
 public:
  /// state_groundtruth_estimate0/data.csv: t, p xyz, q wxyz, v xyz, bg xyz, ba xyz; strictly
  /// increasing time, at least two rows.
  static std::vector<dataset::GroundTruthState> readGroundTruth(const std::string& path);
  /// imu0/data.csv: t, gyro xyz [rad/s], accel xyz [m/s^2]; strictly increasing time.
  static std::vector<ImuSample> readImu(const std::string& path);
  /// `dir` holds cam0/sensor.yaml and cam1/sensor.yaml (and optionally imu0/sensor.yaml), or is
  /// the folder holding mav0/. Missing imu0/sensor.yaml keeps `imu_fallback`.
  static StereoRigCalibration readCalibration(const std::string& dir,
                                              const ImuCalibration& imu_fallback);
};

}  // namespace mcvio::sim
