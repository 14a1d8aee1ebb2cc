#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <opencv2/core.hpp>

#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dataset/euroc_file_reader.hpp"
#include "mcvio/dataset/euroc_writer.hpp"
#include "test_sequence.hpp"

namespace mcvio::dataset {
namespace {

namespace fs = std::filesystem;

// The real EuRoC V1_01 excerpt, or "" when ../shared is not there.
std::string excerptDir() {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  if (!shared) return "";
  const fs::path dir = fs::path(shared) / "data" / "euroc_V1_01_excerpt";
  return fs::is_directory(dir / "mav0") ? dir.string() : "";
}

TEST(EurocRealExcerpt, LoadsWithItsQuirksReported) {
  const std::string dir = excerptDir();
  if (dir.empty()) GTEST_SKIP() << "MCVIO_SHARED_DIR/data/euroc_V1_01_excerpt not present";
  const EurocDataset data = EurocDataset::open(dir);

  ASSERT_EQ(data.stereoFrames().size(), 95u);
  EXPECT_EQ(data.stereoFrames().front().t, 1403715273262142976);
  EXPECT_EQ(data.stereoFrames().back().t, 1403715277962142976);
  // cam1/data.csv lists 99 rows, 4 of them (lines 97-100) without an image.
  ASSERT_EQ(data.warnings().size(), 4u);
  for (int i = 0; i < 4; ++i) {
    const std::string& w = data.warnings()[i];
    EXPECT_NE(w.find("cam1/data.csv:" + std::to_string(97 + i) + ":"), std::string::npos) << w;
    EXPECT_NE(w.find("does not exist"), std::string::npos) << w;
  }
  EXPECT_NE(data.warnings()[0].find("1403715278012143104.png"), std::string::npos);

  ASSERT_EQ(data.imu().size(), 29120u);
  const ImuSample& first = data.imu().front();
  EXPECT_EQ(first.t, 1403715273262142976);
  EXPECT_DOUBLE_EQ(first.gyro.x(), -0.0020943951023931952);
  EXPECT_DOUBLE_EQ(first.accel.x(), 9.0874956666666655);
  EXPECT_DOUBLE_EQ(first.accel.z(), -3.6938381666666662);
  const double duration = toSeconds(data.imu().back().t - first.t);
  EXPECT_NEAR(duration, 145.6, 0.1);

  ASSERT_EQ(data.groundTruth().size(), 2895u);
  const GroundTruthState& gt = data.groundTruth().front();
  EXPECT_EQ(gt.t, 1403715273262142976);
  EXPECT_NEAR(gt.p_WB.x(), 0.878895, 1e-12);
  EXPECT_NEAR(gt.q_WB.w(), 0.069433, 1e-5);  // normalised from 6-digit values
  EXPECT_NEAR(gt.q_WB.x(), -0.824237, 1e-5);
  EXPECT_NEAR(gt.q_WB.norm(), 1.0, 1e-15);
  EXPECT_NEAR(gt.bias_accel.z(), 0.0309774, 1e-12);
  EXPECT_TRUE(data.labels().empty());

  const StereoRigCalibration& rig = data.calibration();
  EXPECT_EQ(rig.cam0.model.width(), 752);
  EXPECT_EQ(rig.cam0.model.height(), 480);
  EXPECT_EQ(rig.cam0.model.fu(), 458.654);
  EXPECT_EQ(rig.cam0.model.fv(), 457.296);
  EXPECT_EQ(rig.cam0.model.cu(), 367.215);
  EXPECT_EQ(rig.cam0.model.cv(), 248.375);
  EXPECT_EQ(rig.cam0.model.distortionModel(), DistortionModel::kRadialTangential);
  EXPECT_EQ(rig.cam0.model.distortionCoefficients(),
            Eigen::Vector4d(-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05));
  EXPECT_EQ(rig.cam1.model.cu(), 379.999);
  EXPECT_EQ(rig.cam1.model.distortionCoefficients()[3], -3.55590700e-05);
  EXPECT_EQ(rig.cam0.rate_hz, 20.0);
  EXPECT_EQ(rig.cam0.T_BC.matrix()(0, 1), -0.999880929698);
  EXPECT_EQ(rig.cam0.T_BC.translation().y(), -0.064676986768);
  EXPECT_EQ(rig.cam1.T_BC.translation().y(), 0.0453689425024);
  EXPECT_NEAR(rig.baseline(), 0.110, 0.001);
  EXPECT_EQ(rig.imu.T_BS.matrix(), Eigen::Matrix4d::Identity());
  EXPECT_EQ(rig.imu.noise.gyroscope_noise_density, 1.6968e-04);
  EXPECT_EQ(rig.imu.noise.gyroscope_random_walk, 1.9393e-05);
  EXPECT_EQ(rig.imu.noise.accelerometer_noise_density, 2.0e-3);
  EXPECT_EQ(rig.imu.noise.accelerometer_random_walk, 3.0e-3);
  EXPECT_EQ(rig.imu.noise.rate_hz, 200.0);

  const cv::Mat left = data.loadImage(data.stereoFrames().front(), 0);
  const cv::Mat right = data.loadImage(data.stereoFrames().back(), 1);
  EXPECT_EQ(left.type(), CV_8UC1);
  EXPECT_EQ(left.cols, 752);
  EXPECT_EQ(right.rows, 480);
  EXPECT_GT(cv::mean(left)[0], 10.0);  // a real picture, not a blank
}

TEST(EurocRealExcerpt, SingleFilesReadAlone) {
  const std::string dir = excerptDir();
  if (dir.empty()) GTEST_SKIP() << "MCVIO_SHARED_DIR/data/euroc_V1_01_excerpt not present";
  const auto gt =
      EurocFileReader::readGroundTruth(dir + "/mav0/state_groundtruth_estimate0/data.csv");
  ASSERT_EQ(gt.size(), 2895u);
  EXPECT_EQ(gt.back().t, 1403715417962142976);
  EXPECT_EQ(EurocFileReader::readImu(dir + "/mav0/imu0/data.csv").size(), 29120u);
  const StereoRigCalibration rig = EurocFileReader::readCalibration(dir);
  EXPECT_EQ(rig.cam1.model.fu(), 457.587);
  EXPECT_EQ(rig.cam1.name, "cam1");
}

TEST(EurocRealExcerpt, RewrittenExcerptReadsBackTheSame) {
  const std::string dir = excerptDir();
  if (dir.empty()) GTEST_SKIP() << "MCVIO_SHARED_DIR/data/euroc_V1_01_excerpt not present";
  const EurocDataset data = EurocDataset::open(dir);
  const std::string out = test::freshDir("real_rewrite");
  {
    EurocWriter::Options options;
    options.png_compression = 1;
    EurocWriter writer(out, data.calibration(), options);
    for (int i = 0; i < 5; ++i) {  // a few frames keep the test fast; all IMU and ground truth
      const StereoFrame& f = data.stereoFrames()[i];
      writer.addStereoFrame(f.t, data.loadImage(f, 0), data.loadImage(f, 1));
    }
    for (const ImuSample& s : data.imu()) writer.addImu(s);
    for (const GroundTruthState& s : data.groundTruth()) writer.addGroundTruth(s);
  }
  const EurocDataset again = EurocDataset::open(out);
  EXPECT_TRUE(again.warnings().empty());
  ASSERT_EQ(again.stereoFrames().size(), 5u);
  EXPECT_EQ(cv::norm(again.loadImage(again.stereoFrames()[4], 1),
                     data.loadImage(data.stereoFrames()[4], 1), cv::NORM_INF),
            0.0);
  ASSERT_EQ(again.imu().size(), data.imu().size());
  for (std::size_t i = 0; i < data.imu().size(); ++i) {
    ASSERT_EQ(again.imu()[i].t, data.imu()[i].t);
    ASSERT_EQ(again.imu()[i].gyro, data.imu()[i].gyro);
    ASSERT_EQ(again.imu()[i].accel, data.imu()[i].accel);
  }
  ASSERT_EQ(again.groundTruth().size(), data.groundTruth().size());
  for (std::size_t i = 0; i < data.groundTruth().size(); ++i) {
    ASSERT_EQ(again.groundTruth()[i].q_WB.coeffs(), data.groundTruth()[i].q_WB.coeffs()) << i;
    ASSERT_EQ(again.groundTruth()[i].p_WB, data.groundTruth()[i].p_WB);
  }
  EXPECT_EQ(again.calibration().cam0.T_BC.matrix(), data.calibration().cam0.T_BC.matrix());
  EXPECT_EQ(again.calibration().cam1.model.distortionCoefficients(),
            data.calibration().cam1.model.distortionCoefficients());
}

}  // namespace
}  // namespace mcvio::dataset
