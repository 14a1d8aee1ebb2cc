#pragma once
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/dataset/conflict_label.hpp"
#include "mcvio/dataset/euroc_dataset_options.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"
#include "mcvio/dataset/stereo_frame.hpp"

namespace mcvio::dataset {

/// A EuRoC ASL folder opened for reading.
///
/// Layout (below `dir` or `dir/mav0`):
///   cam0/, cam1/          sensor.yaml, data.csv ("#timestamp [ns],filename"), data/<t>.png
///   imu0/                 sensor.yaml, data.csv (t, gyro xyz [rad/s], accel xyz [m/s^2])
///   state_groundtruth_estimate0/data.csv   optional: t, p xyz, q wxyz, v xyz, bg xyz, ba xyz
///   conflict_labels.csv   optional: t, in_conflict 0/1, motion, covered_fraction
///
/// open() reads the calibration, the IMU, ground truth and labels, and lists the stereo frames;
/// images stay on disk until loadImage(). Rows that cannot be used without making the rest of
/// the sequence wrong are reported in warnings() and skipped: cam1 rows whose image is missing
/// (real EuRoC has them), cam0/cam1 frames without a partner, a missing ground-truth file.
/// Everything else that is wrong (missing folder or file, malformed row, time not strictly
/// increasing, NaN/inf, bad sensor.yaml, image size contradicting sensor.yaml) throws
/// mcvio::InputError whose message names the file and, for CSV rows, the line; see
/// EurocDatasetOptions::skip_bad_rows to skip bad rows instead.
///
/// Usage:
///   auto data = mcvio::dataset::EurocDataset::open("/data/V1_01_easy");
///   for (const auto& w : data.warnings()) std::cerr << w << "\n";
///   for (const auto& frame : data.stereoFrames()) {
///     cv::Mat left = data.loadImage(frame, 0), right = data.loadImage(frame, 1);
///   }
///
/// A const EurocDataset is safe to use from several threads.
class EurocDataset {
 public:
  /// Opens `dir` (the folder holding mav0/, or mav0/ itself). Throws mcvio::InputError.
  static EurocDataset open(const std::string& dir, const EurocDatasetOptions& options = {});

  /// The mav0 folder that was read.
  const std::string& root() const { return root_; }
  /// cam0, cam1 (from their sensor.yaml) and imu0.
  const StereoRigCalibration& calibration() const { return calibration_; }
  /// Stereo pairs in increasing time; image paths are absolute.
  const std::vector<StereoFrame>& stereoFrames() const { return frames_; }
  /// IMU samples in strictly increasing time.
  const std::vector<ImuSample>& imu() const { return imu_; }
  /// Ground truth in strictly increasing time; empty when the data set has none.
  const std::vector<GroundTruthState>& groundTruth() const { return ground_truth_; }
  /// Per-frame conflict labels in strictly increasing time; empty without conflict_labels.csv.
  const std::vector<ConflictLabel>& labels() const { return labels_; }
  /// One message per skipped row or missing optional part, naming the file (and line).
  const std::vector<std::string>& warnings() const { return warnings_; }

  /// Loads camera `camera`'s (0 or 1) image of `frame` as 8-bit mono. Throws mcvio::InputError
  /// naming the file if it cannot be decoded or its size differs from sensor.yaml.
  cv::Mat loadImage(const StereoFrame& frame, int camera) const;
  /// Same for any image path, checked against camera `camera`'s resolution.
  cv::Mat loadImage(const std::string& path, int camera) const;
  /// As loadImage(), but a file that cannot be read or decoded (one corrupt frame in a long
  /// recording) returns false with `error` naming it instead of throwing. A size that differs
  /// from sensor.yaml still throws: that is the calibration's problem, not one frame's.
  bool tryLoadImage(const StereoFrame& frame, int camera, cv::Mat* image, std::string* error) const;

 private:
  EurocDataset() = default;
  /// Decodes `path` as 8-bit mono; false with `error` naming the file when it cannot be read or
  /// is damaged. A PNG left to OpenCV whose header gives another size than camera `camera`'s (a
  /// 20-megapixel photo in cam0/data) throws before it is decoded.
  bool decode(const std::string& path, int camera, cv::Mat* image, std::string* error) const;
  void checkSize(const std::string& path, int width, int height, int camera) const;

  std::string root_;
  StereoRigCalibration calibration_;
  std::vector<StereoFrame> frames_;
  std::vector<ImuSample> imu_;
  std::vector<GroundTruthState> ground_truth_;
  std::vector<ConflictLabel> labels_;
  std::vector<std::string> warnings_;
};

}  // namespace mcvio::dataset
