#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "mcvio/core/input_error.hpp"
#include "mcvio/sim/recorded_sequence_reader.hpp"
#include "mcvio/sim/simulator.hpp"

namespace mcvio::sim {
namespace {

std::string excerptDir() {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  if (!shared) return {};
  const std::string dir = std::string(shared) + "/data/euroc_V1_01_excerpt/mav0";
  return std::filesystem::exists(dir) ? dir : std::string();
}

SimulatorOptions semiReal(const std::string& mav0, ScenarioKind kind) {
  SimulatorOptions o;
  o.groundtruth_csv = mav0 + "/state_groundtruth_estimate0/data.csv";
  o.imu_csv = mav0 + "/imu0/data.csv";
  o.calibration_dir = mav0;
  o.texture_size = 256;
  o.scenario.kind = kind;
  o.scenario.onset_s = 30.0;
  o.scenario.duration_s = 10.0;
  return o;
}

TEST(SemiReal, RendersAlongTheRealTrajectoryAndKeepsTheRealImu) {
  const std::string mav0 = excerptDir();
  if (mav0.empty()) GTEST_SKIP() << "shared EuRoC excerpt absent";
  const auto real_imu = RecordedSequenceReader::readImu(mav0 + "/imu0/data.csv");
  const auto real_gt = RecordedSequenceReader::readGroundTruth(mav0 + "/state_groundtruth_estimate0/data.csv");
  Simulator sim(semiReal(mav0, ScenarioKind::kNone));
  ASSERT_GT(sim.frameTimes().size(), 2800u);  // 144.7 s at 20 Hz
  EXPECT_EQ(sim.frameTimes().front(), real_gt.front().t);
  // The IMU is the recording's, sample for sample, inside the ground truth's time span.
  std::size_t first = 0;
  while (real_imu[first].t < sim.frameTimes().front()) ++first;
  ASSERT_GT(sim.imu().size(), 28000u);
  for (std::size_t k = 0; k < sim.imu().size(); k += 97) {
    EXPECT_EQ(sim.imu()[k].t, real_imu[first + k].t);
    EXPECT_EQ(sim.imu()[k].accel, real_imu[first + k].accel);
  }
  // The camera is where the ground truth puts it.
  const StereoRender f = sim.renderFrame(1500);
  const Eigen::Isometry3d T = sim.bodyPose(f.t);
  EXPECT_LT((T.translation() - real_gt[1500].p_WB).norm(), 1e-9);
  cv::Scalar mean, stddev;
  cv::meanStdDev(f.cam0, mean, stddev);
  EXPECT_GT(stddev[0], 20.0);
  EXPECT_FALSE(f.label.in_conflict);
}

TEST(SemiReal, AnElevatorRideIsAddedToTheRealImuAndGroundTruth) {
  const std::string mav0 = excerptDir();
  if (mav0.empty()) GTEST_SKIP() << "shared EuRoC excerpt absent";
  Simulator plain(semiReal(mav0, ScenarioKind::kNone));
  Simulator ride(semiReal(mav0, ScenarioKind::kElevator));
  ASSERT_EQ(plain.imu().size(), ride.imu().size());
  const Timestamp onset = ride.frameTimes().front() + fromSeconds(30.0);
  const Timestamp end = onset + fromSeconds(10.0);
  double max_extra = 0;
  for (std::size_t k = 0; k < ride.imu().size(); ++k) {
    const ImuSample& a = plain.imu()[k];
    const ImuSample& b = ride.imu()[k];
    EXPECT_EQ(a.gyro, b.gyro);
    const double extra = (b.accel - a.accel).norm();
    if (a.t <= onset || a.t >= end) {
      EXPECT_EQ(extra, 0.0) << "outside the ride the IMU is untouched";
    }
    max_extra = std::max(max_extra, extra);
  }
  // Peak cabin acceleration 2 pi L / D^2 = 2 pi 12 / 100.
  EXPECT_NEAR(max_extra, 2 * M_PI * 12.0 / 100.0, 0.01);
  EXPECT_NEAR(ride.groundTruth().back().p_WB.z() - plain.groundTruth().back().p_WB.z(), 12.0, 1e-9);
  // The camera sees the cabin around it: in conflict during the ride only.
  const std::size_t mid = 20 * 35;
  EXPECT_TRUE(ride.renderFrame(mid).label.in_conflict);
  EXPECT_FALSE(ride.renderFrame(20 * 20).label.in_conflict);
}

TEST(SemiReal, BadRecordingsAreReportedWithFileAndLine) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "mcvio_sim_bad_recording";
  std::filesystem::create_directories(dir);
  const std::string gt = (dir / "gt.csv").string(), imu = (dir / "imu.csv").string();
  auto write = [](const std::string& path, const std::string& text) {
    FILE* f = std::fopen(path.c_str(), "w");
    std::fputs(text.c_str(), f);
    std::fclose(f);
  };
  write(gt, "#t,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n"
            "1000,0,0,1,1,0,0,0,0,0,0,0,0,0,0,0,0\n"
            "900,0,0,1,1,0,0,0,0,0,0,0,0,0,0,0,0\n");
  write(imu, "#t,wx,wy,wz,ax,ay,az\n1000,0,0,0,0,0,nan\n");
  auto message = [](auto&& fn) {
    try {
      fn();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string m1 = message([&] { RecordedSequenceReader::readGroundTruth(gt); });
  EXPECT_NE(m1.find("gt.csv:3"), std::string::npos) << m1;
  const std::string m2 = message([&] { RecordedSequenceReader::readImu(imu); });
  EXPECT_NE(m2.find("imu.csv:2"), std::string::npos) << m2;
  const std::string m3 = message([&] { RecordedSequenceReader::readImu((dir / "missing.csv").string()); });
  EXPECT_NE(m3.find("missing.csv"), std::string::npos) << m3;
  SimulatorOptions o;
  o.groundtruth_csv = gt;
  o.imu_csv = imu;
  EXPECT_THROW(Simulator{o}, InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mcvio::sim
