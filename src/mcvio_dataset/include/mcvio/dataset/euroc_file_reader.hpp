#pragma once
#include <string>
#include <vector>

#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/dataset/conflict_label.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"

namespace mcvio::dataset {

/// The single files of a EuRoC folder, for callers that need one part without the rest (a
/// ground-truth trajectory, the IMU stream, the calibration). EurocDataset::open uses these.
///
/// Each throws mcvio::InputError naming the file and line for a missing file, a wrong column
/// count, a field that is not a number, NaN/inf, or time that does not strictly increase. With
/// skip_bad_rows such rows are skipped instead and reported in `warnings` (when non-null).
class EurocFileReader {
 public:
  /// imu0/data.csv: t [ns], gyro xyz [rad/s], accel xyz [m/s^2]. At least one sample.
  static std::vector<ImuSample> readImu(const std::string& path, bool skip_bad_rows = false,
                                        std::vector<std::string>* warnings = nullptr);
  /// state_groundtruth_estimate0/data.csv: t, p xyz, q wxyz, v xyz, bg xyz, ba xyz (17 columns).
  /// Quaternions must have norm 1 +- 1e-3 and are normalised (unit ones are left bit-exact).
  static std::vector<GroundTruthState> readGroundTruth(
      const std::string& path, bool skip_bad_rows = false,
      std::vector<std::string>* warnings = nullptr);
  /// conflict_labels.csv: t, in_conflict 0/1, motion, covered_fraction in [0, 1].
  static std::vector<ConflictLabel> readLabels(const std::string& path, bool skip_bad_rows = false,
                                               std::vector<std::string>* warnings = nullptr);
  /// cam0/, cam1/ and imu0/sensor.yaml below `dir` (the folder holding mav0/, or mav0/ itself).
  /// `warnings` (if given) gets one line per key of those files that is not read
  /// (SensorYaml::unreadKeys).
  static StereoRigCalibration readCalibration(const std::string& dir, std::vector<std::string>* warnings = nullptr);
};

}  // namespace mcvio::dataset
