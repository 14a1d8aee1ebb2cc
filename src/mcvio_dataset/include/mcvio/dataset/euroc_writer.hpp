#pragma once
#include <cstdio>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>

#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/dataset/conflict_label.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"

namespace mcvio::dataset {

/// Streams a sequence to disk as a EuRoC ASL folder that EurocDataset (and other EuRoC tools)
/// read back: `dir/mav0/{cam0,cam1,imu0,state_groundtruth_estimate0}` with real EuRoC CSV
/// headers, PNG images, sensor.yaml files, and mav0/conflict_labels.csv when labels are added.
/// Rows go to disk as they are added, so memory stays flat; every double is written with the
/// shortest text that reads back to the same value, so write-then-read is lossless.
///
/// Each stream (each camera, IMU, ground truth, labels) needs strictly increasing timestamps
/// and finite values; violations throw std::invalid_argument and nothing is written for that
/// call. I/O failures throw mcvio::InputError naming the file.
///
///   mcvio::dataset::EurocWriter out("/tmp/seq", rig);
///   out.addStereoFrame(t, left, right);  // CV_8UC1 images of the calibrated size
///   out.addImu(sample);
///   out.close();                         // or let the destructor close
class EurocWriter {
 public:
  struct Options {
    /// PNG zlib level 0-9: lower is faster, higher smaller. Every level is lossless.
    int png_compression = 3;
    /// If dir/mav0 exists: true deletes it first, false throws mcvio::InputError.
    bool overwrite = false;
  };

  /// Creates the folders and writes the sensor.yaml files (ground truth's when the first
  /// state is added).
  EurocWriter(const std::string& dir, const StereoRigCalibration& calibration,
              const Options& options);
  EurocWriter(const std::string& dir, const StereoRigCalibration& calibration)
      : EurocWriter(dir, calibration, Options()) {}
  /// Closes the files; errors at this point are swallowed, call close() to see them.
  ~EurocWriter();
  EurocWriter(const EurocWriter&) = delete;
  EurocWriter& operator=(const EurocWriter&) = delete;

  /// Writes both images of a stereo pair at time t (cam0 and cam1 share it).
  void addStereoFrame(Timestamp t, const cv::Mat& cam0, const cv::Mat& cam1);
  /// Writes one camera's image (CV_8UC1, width x height of that camera's calibration).
  void addImage(int camera, Timestamp t, const cv::Mat& image);
  void addImu(const ImuSample& sample);
  void addGroundTruth(const GroundTruthState& state);
  void addLabel(const ConflictLabel& label);

  /// Flushes and closes every file; throws mcvio::InputError if a write failed. Further adds
  /// throw std::logic_error.
  void close();

  /// The mav0 folder being written.
  const std::string& root() const { return root_; }

 private:
  struct Stream {
    std::string path;
    std::FILE* file = nullptr;
    Timestamp last_t = 0;
    bool has_rows = false;
    Stream() = default;
    Stream(const Stream&) = delete;
    Stream& operator=(const Stream&) = delete;
    ~Stream() {
      if (file) std::fclose(file);
    }
  };
  void openStream(Stream* stream, const std::string& path, const char* header);
  void checkTime(Stream* stream, Timestamp t, const char* what) const;
  void writeLine(Stream* stream, const std::string& line);
  void checkOpen() const;

  std::string root_;
  StereoRigCalibration calibration_;
  Options options_;
  Stream cam_[2];
  Stream imu_;
  Stream ground_truth_;
  Stream labels_;
  bool closed_ = false;
  std::string line_;  // reused row buffer
};

}  // namespace mcvio::dataset
