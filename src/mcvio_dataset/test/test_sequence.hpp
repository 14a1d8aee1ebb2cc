#pragma once
// Deterministic synthetic EuRoC sequences for the dataset tests.
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/dataset/conflict_label.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"

namespace mcvio::dataset::test {

/// Everything a synthetic sequence holds, as written.
struct TestSequence {
  StereoRigCalibration rig;
  std::vector<Timestamp> frame_times;
  std::vector<cv::Mat> cam0, cam1;
  std::vector<ImuSample> imu;
  std::vector<GroundTruthState> ground_truth;
  std::vector<ConflictLabel> labels;
};

/// A small rig (cam0 radial-tangential, cam1 equidistant, 64x48 images) with awkward doubles.
StereoRigCalibration makeRig();
/// `frames` stereo frames at 20 Hz, IMU at 200 Hz, ground truth and labels per frame.
TestSequence makeSequence(int frames, unsigned seed);
/// Writes `seq` below `dir` with EurocWriter (overwriting).
void writeSequence(const std::string& dir, const TestSequence& seq, bool with_ground_truth = true,
                   bool with_labels = true);
/// A fresh empty folder for one test, removed first if it exists.
std::string freshDir(const std::string& name);
/// Whole-file text helpers for corrupting files.
std::string readText(const std::string& path);
void writeText(const std::string& path, const std::string& text);
/// Replaces the 1-based line `line` of a text file.
void replaceLine(const std::string& path, int line, const std::string& text);

}  // namespace mcvio::dataset::test
