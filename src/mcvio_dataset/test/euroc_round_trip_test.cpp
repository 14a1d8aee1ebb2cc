#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dataset/euroc_writer.hpp"
#include "test_sequence.hpp"

namespace mcvio::dataset {
namespace {

namespace fs = std::filesystem;
using test::freshDir;
using test::makeSequence;
using test::writeSequence;

void expectSameCamera(const CameraCalibration& a, const CameraCalibration& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.model.width(), b.model.width());
  EXPECT_EQ(a.model.height(), b.model.height());
  EXPECT_EQ(a.model.intrinsics(), b.model.intrinsics());
  EXPECT_EQ(a.model.distortionModel(), b.model.distortionModel());
  EXPECT_EQ(a.model.distortionCoefficients(), b.model.distortionCoefficients());
  EXPECT_EQ(a.rate_hz, b.rate_hz);
  EXPECT_EQ(a.T_BC.matrix(), b.T_BC.matrix());
}

TEST(EurocRoundTrip, WriteThenReadIsLossless) {
  const std::string dir = freshDir("round_trip");
  const test::TestSequence seq = makeSequence(12, 1);
  writeSequence(dir, seq);

  const EurocDataset data = EurocDataset::open(dir);
  EXPECT_TRUE(data.warnings().empty()) << data.warnings().front();
  expectSameCamera(data.calibration().cam0, seq.rig.cam0);
  expectSameCamera(data.calibration().cam1, seq.rig.cam1);
  EXPECT_EQ(data.calibration().imu.T_BS.matrix(), seq.rig.imu.T_BS.matrix());
  EXPECT_EQ(data.calibration().imu.noise.gyroscope_noise_density,
            seq.rig.imu.noise.gyroscope_noise_density);
  EXPECT_EQ(data.calibration().imu.noise.gyroscope_random_walk,
            seq.rig.imu.noise.gyroscope_random_walk);
  EXPECT_EQ(data.calibration().imu.noise.accelerometer_noise_density,
            seq.rig.imu.noise.accelerometer_noise_density);
  EXPECT_EQ(data.calibration().imu.noise.accelerometer_random_walk,
            seq.rig.imu.noise.accelerometer_random_walk);
  EXPECT_EQ(data.calibration().imu.noise.rate_hz, seq.rig.imu.noise.rate_hz);

  ASSERT_EQ(data.stereoFrames().size(), seq.frame_times.size());
  for (std::size_t i = 0; i < seq.frame_times.size(); ++i) {
    const StereoFrame& f = data.stereoFrames()[i];
    EXPECT_EQ(f.t, seq.frame_times[i]);
    EXPECT_EQ(f.t_cam1, seq.frame_times[i]);
    const cv::Mat left = data.loadImage(f, 0), right = data.loadImage(f, 1);
    ASSERT_EQ(left.type(), CV_8UC1);
    EXPECT_EQ(cv::norm(left, seq.cam0[i], cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(right, seq.cam1[i], cv::NORM_INF), 0.0);
  }
  ASSERT_EQ(data.imu().size(), seq.imu.size());
  for (std::size_t i = 0; i < seq.imu.size(); ++i) {
    EXPECT_EQ(data.imu()[i].t, seq.imu[i].t);
    EXPECT_EQ(data.imu()[i].gyro, seq.imu[i].gyro);
    EXPECT_EQ(data.imu()[i].accel, seq.imu[i].accel);
  }
  ASSERT_EQ(data.groundTruth().size(), seq.ground_truth.size());
  for (std::size_t i = 0; i < seq.ground_truth.size(); ++i) {
    const GroundTruthState &a = data.groundTruth()[i], &b = seq.ground_truth[i];
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.p_WB, b.p_WB);
    EXPECT_EQ(a.q_WB.coeffs(), b.q_WB.coeffs());
    EXPECT_EQ(a.v_WB, b.v_WB);
    EXPECT_EQ(a.bias_gyro, b.bias_gyro);
    EXPECT_EQ(a.bias_accel, b.bias_accel);
  }
  ASSERT_EQ(data.labels().size(), seq.labels.size());
  for (std::size_t i = 0; i < seq.labels.size(); ++i) {
    EXPECT_EQ(data.labels()[i].t, seq.labels[i].t);
    EXPECT_EQ(data.labels()[i].in_conflict, seq.labels[i].in_conflict);
    EXPECT_EQ(data.labels()[i].motion, seq.labels[i].motion);
    EXPECT_EQ(data.labels()[i].covered_fraction, seq.labels[i].covered_fraction);
  }
}

TEST(EurocRoundTrip, OpensMav0FolderDirectlyAndWritesEurocHeaders) {
  const std::string dir = freshDir("mav0_direct");
  writeSequence(dir, makeSequence(3, 2));
  const EurocDataset data = EurocDataset::open(dir + "/mav0");
  EXPECT_EQ(data.stereoFrames().size(), 3u);
  EXPECT_EQ(test::readText(dir + "/mav0/cam0/data.csv").rfind("#timestamp [ns],filename\n", 0), 0u);
  EXPECT_EQ(
      test::readText(dir + "/mav0/imu0/data.csv").rfind("#timestamp [ns],w_RS_S_x [rad s^-1]", 0),
      0u);
  EXPECT_EQ(test::readText(dir + "/mav0/cam0/sensor.yaml").rfind("%YAML:1.0\n", 0), 0u);
  EXPECT_TRUE(fs::exists(dir + "/mav0/cam1/data/1403715273262142976.png"));
}

TEST(EurocRoundTrip, GroundTruthAndLabelsAreOptional) {
  const std::string dir = freshDir("optional_parts");
  writeSequence(dir, makeSequence(4, 3), /*with_ground_truth=*/false, /*with_labels=*/false);
  EXPECT_FALSE(fs::exists(dir + "/mav0/state_groundtruth_estimate0"));
  EXPECT_FALSE(fs::exists(dir + "/mav0/conflict_labels.csv"));
  const EurocDataset data = EurocDataset::open(dir);
  EXPECT_TRUE(data.groundTruth().empty());
  EXPECT_TRUE(data.labels().empty());
  EXPECT_TRUE(data.warnings().empty());
  EXPECT_EQ(data.stereoFrames().size(), 4u);
}

TEST(EurocWriter, RejectsBadCallsWithoutWritingThem) {
  const std::string dir = freshDir("writer_rejects");
  const test::TestSequence seq = makeSequence(2, 4);
  EurocWriter writer(dir, seq.rig);
  writer.addStereoFrame(seq.frame_times[0], seq.cam0[0], seq.cam1[0]);
  // Time not increasing.
  EXPECT_THROW(writer.addStereoFrame(seq.frame_times[0], seq.cam0[1], seq.cam1[1]),
               std::invalid_argument);
  // Wrong size and type.
  EXPECT_THROW(writer.addStereoFrame(seq.frame_times[1], cv::Mat(10, 10, CV_8UC1), seq.cam1[1]),
               std::invalid_argument);
  EXPECT_THROW(writer.addImage(1, seq.frame_times[1], cv::Mat(48, 64, CV_16UC1)),
               std::invalid_argument);
  ImuSample bad;
  bad.t = 5;
  bad.gyro.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(writer.addImu(bad), std::invalid_argument);
  ConflictLabel label;
  label.t = 1;
  label.motion = "a,b";
  EXPECT_THROW(writer.addLabel(label), std::invalid_argument);
  label.motion = "elevator";
  label.covered_fraction = 1.5;
  EXPECT_THROW(writer.addLabel(label), std::invalid_argument);
  writer.addStereoFrame(seq.frame_times[1], seq.cam0[1], seq.cam1[1]);
  writer.addImu(seq.imu[0]);
  writer.close();
  EXPECT_THROW(writer.addImu(seq.imu[1]), std::logic_error);

  const EurocDataset data = EurocDataset::open(dir);
  EXPECT_EQ(data.stereoFrames().size(), 2u);  // the rejected pair left nothing behind
  EXPECT_TRUE(data.warnings().empty());
  EXPECT_EQ(data.imu().size(), 1u);
}

TEST(EurocWriter, RefusesExistingFolderUnlessOverwrite) {
  const std::string dir = freshDir("writer_existing");
  const test::TestSequence seq = makeSequence(1, 5);
  { EurocWriter writer(dir, seq.rig); }
  try {
    EurocWriter again(dir, seq.rig);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/mav0"), std::string::npos) << e.what();
  }
  EurocWriter::Options options;
  options.overwrite = true;
  EXPECT_NO_THROW(EurocWriter(dir, seq.rig, options));
}

}  // namespace
}  // namespace mcvio::dataset
