// The backend component on the bus. Player -> FrontendComponent -> BackendComponent, all lossless,
// on the real excerpt: the backend's poses are those of an offline estimator fed the same feature
// frames and the data set's IMU up to each frame (to 1e-6), and the same frames as `mcvio run`'s.
// Bad input (NaN IMU, stamps going back, frames without features or without IMU) is logged and
// skipped, and no pose is published before the estimator is initialised.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "mcvio/components/backend_component.hpp"
#include "mcvio/components/frontend_component.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/dataset/euroc_file_reader.hpp"
#include "mcvio/dataset/kalibr_calibration.hpp"
#include "mcvio/estimator/sliding_window_estimator.hpp"
#include "mcvio/pipeline/offline_run.hpp"
#include "mcvio/sim/euroc_rig_defaults.hpp"
#include "mcvio/sim/simulator.hpp"
#include "component_test_support.hpp"

using namespace mcvio;
using namespace std::chrono_literals;

namespace {

using Odometry = nav_msgs::msg::dds_::Odometry_;
using components::stampOf;

using components::test::excerptDir;
using components::test::testParticipantOptions;

struct Pose {
  Timestamp t = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};

Pose poseOf(const Odometry& m) {
  const auto& p = m.pose().pose();
  return {stampOf(m.header()), {p.position().x(), p.position().y(), p.position().z()},
          Eigen::Quaterniond(p.orientation().w(), p.orientation().x(), p.orientation().y(), p.orientation().z())};
}

// trajectory.tum: t[s] x y z qx qy qz qw
std::vector<Pose> readTum(const std::string& path) {
  std::vector<Pose> v;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double t, x, y, z, qx, qy, qz, qw;
    s >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
    v.push_back({static_cast<Timestamp>(std::llround(t * 1e9)), {x, y, z}, Eigen::Quaterniond(qw, qx, qy, qz)});
  }
  return v;
}

// Largest position difference [m] and rotation angle [rad] between two equally long pose lists.
std::pair<double, double> maxDifference(const std::vector<Pose>& a, const std::vector<Pose>& b) {
  double dp = 0, dq = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    dp = std::max(dp, (a[i].p - b[i].p).norm());
    dq = std::max(dq, a[i].q.angularDistance(b[i].q));
  }
  return {dp, dq};
}

template <class Pred>
bool waitUntil(Pred pred, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (pred()) return true;
    std::this_thread::sleep_for(20ms);
  }
  return pred();
}

// What a lossless Player -> FrontendComponent -> BackendComponent run on `dir` gave, checked
// against the estimator fed offline with the same feature frames; returns the DDS poses.
std::vector<Pose> runOverDdsAndCheckTheEstimatorStage(const std::string& dir, int salt) {
  const auto data = dataset::EurocDataset::open(dir);
  auto participant = mcvio::dds::Participant::create(testParticipantOptions(salt));

  std::mutex m;
  std::vector<Pose> odometry;
  std::vector<FeatureFrame> features;
  std::size_t conflict_messages = 0, tf_messages = 0, landmark_clouds = 0;
  Odometry first_odometry;
  auto listener = participant->createNode("listener");
  const auto lossless = mcvio::dds::QosProfile::lossless();
  auto odom_sub = listener->createSubscription<Odometry>("/mcvio/odometry", lossless, [&](const Odometry& o) {
    std::lock_guard<std::mutex> lock(m);
    if (odometry.empty()) first_odometry = o;
    odometry.push_back(poseOf(o));
  });
  auto features_sub = listener->createSubscription<mcvio_msgs::msg::dds_::FeatureFrame_>(
      "/mcvio/features", lossless, [&](const mcvio_msgs::msg::dds_::FeatureFrame_& f) {
        std::lock_guard<std::mutex> lock(m);
        features.push_back(components::fromFeatureFrameMsg(f));
      });
  auto conflict_sub = listener->createSubscription<mcvio_msgs::msg::dds_::MotionConflict_>(
      "/mcvio/conflict", lossless, [&](const auto&) { std::lock_guard<std::mutex> lock(m); ++conflict_messages; });
  auto tf_sub = listener->createSubscription<tf2_msgs::msg::dds_::TFMessage_>(
      "/tf", lossless, [&](const auto&) { std::lock_guard<std::mutex> lock(m); ++tf_messages; });
  auto cloud_sub = listener->createSubscription<sensor_msgs::msg::dds_::PointCloud2_>(
      "/mcvio/landmarks", lossless, [&](const auto&) { std::lock_guard<std::mutex> lock(m); ++landmark_clouds; });

  components::BackendComponentOptions bo;
  bo.calibration_dir = dir;
  bo.lossless = true;
  components::BackendComponent backend(participant->createNode("backend"), bo);
  components::FrontendComponentOptions fo;
  fo.calibration_dir = dir;
  fo.lossless = true;
  components::FrontendComponent frontend(participant->createNode("frontend"), fo);

  // A late joiner gets the static transforms (transient local).
  std::vector<geometry_msgs::msg::dds_::TransformStamped_> statics;
  auto static_sub = listener->createSubscription<tf2_msgs::msg::dds_::TFMessage_>(
      "/tf_static", mcvio::dds::QosProfile::transientLocal(1), [&](const tf2_msgs::msg::dds_::TFMessage_& t) {
        std::lock_guard<std::mutex> lock(m);
        statics = t.transforms();
      });

  auto player_participant = mcvio::dds::Participant::create(testParticipantOptions(salt));
  components::PlayerOptions po;
  po.lossless = true;
  po.progress = false;
  po.min_readers = 1;
  po.wait_for_readers_s = 20;
  components::Player player(player_participant->createNode("player"), data, po);
  std::thread feeder([&] {
    auto extra = player_participant->createNode("extra_readers");
    auto a = extra->createSubscription<sensor_msgs::msg::dds_::CameraInfo_>("/cam0/camera_info", lossless, [](const auto&) {});
    auto b = extra->createSubscription<sensor_msgs::msg::dds_::CameraInfo_>("/cam1/camera_info", lossless, [](const auto&) {});
    auto c = extra->createSubscription<Odometry>("/ground_truth/odometry", lossless, [](const auto&) {});
    player.run();
  });
  feeder.join();
  const std::size_t pairs = data.stereoFrames().size();
  EXPECT_TRUE(waitUntil([&] { const auto s = frontend.stats(); return s.frames_published + s.frames_skipped == pairs; }, 120s));
  const std::size_t published = frontend.stats().frames_published;
  EXPECT_TRUE(waitUntil([&] { return backend.stats().frames_received == published; }, 30s));
  backend.flush();
  const auto stats = backend.stats();
  EXPECT_TRUE(waitUntil([&] { std::lock_guard<std::mutex> lock(m); return odometry.size() == stats.poses_published && features.size() == published; }, 30s));

  std::lock_guard<std::mutex> lock(m);
  EXPECT_EQ(stats.frames_processed, published);
  EXPECT_EQ(stats.frames_dropped, 0u);
  EXPECT_EQ(stats.imu_rejected, 0u);
  EXPECT_GT(stats.poses_published, 0u);
  EXPECT_EQ(conflict_messages, stats.poses_published);
  EXPECT_TRUE(waitUntil([&] { return tf_messages == stats.poses_published && landmark_clouds == stats.poses_published; }, 5s));
  EXPECT_EQ(statics.size(), 2u);
  if (statics.size() == 2) {
    EXPECT_EQ(statics[0].header().frame_id(), "imu0");
    EXPECT_EQ(statics[0].child_frame_id(), "cam0");
  }
  EXPECT_EQ(first_odometry.header().frame_id(), "world");
  EXPECT_EQ(first_odometry.child_frame_id(), "imu0");
  EXPECT_GT(first_odometry.pose().covariance()[0], 0.0);

  // The estimator stage on its own, offline: the same feature frames, with the data set's IMU up to
  // each frame's time first. The backend must give exactly these poses.
  const auto rig = dataset::EurocFileReader::readCalibration(dir);
  estimator::SlidingWindowEstimator reference(components::BackendComponentOptions{}.estimator, rig);
  std::vector<Pose> expected;
  std::size_t next_imu = 0;
  for (const auto& f : features) {
    while (next_imu < data.imu().size() && data.imu()[next_imu].t <= f.t) reference.addImu(data.imu()[next_imu++]);
    const auto e = reference.addFrame(f);
    if (e.status == estimator::EstimatorStatus::kTracking && e.frame_accepted) expected.push_back({e.t, e.p_WB, e.q_WB});
  }
  EXPECT_EQ(odometry.size(), expected.size());
  for (std::size_t i = 0; i < std::min(odometry.size(), expected.size()); ++i) EXPECT_EQ(odometry[i].t, expected[i].t) << i;
  const auto [dp, dq] = maxDifference(odometry, expected);
  std::cout << "backend vs offline estimator on the same features: " << odometry.size() << " poses, max difference "
            << dp << " m, " << dq << " rad; backend latency mean " << stats.latency_ms_mean << " ms, max "
            << stats.latency_ms_max << " ms; estimator CPU mean " << stats.estimator_cpu_ms_mean << " ms\n";
  // Bit for bit (the estimator's blocks live in its own pools, so its arithmetic does not follow
  // the heap of the process it runs in); the rotation's distance carries acos rounding only.
  EXPECT_EQ(dp, 0.0);
  EXPECT_LT(dq, 1e-12);
  return odometry;
}

// The same data through `mcvio run`: the same frames get a pose, and the poses agree to
// `tolerance`.
void compareWithOfflineRun(const std::string& dir, const std::vector<Pose>& odometry, double tolerance) {
  pipeline::OfflineRunOptions ro;
  ro.dataset_dir = dir;
  ro.output_dir = ::testing::TempDir() + "/backend_component_" + std::to_string(getpid());
  ro.progress = false;
  pipeline::runOffline(ro);
  const auto offline = readTum(ro.output_dir + "/trajectory.tum");
  std::filesystem::remove_all(ro.output_dir);
  ASSERT_EQ(odometry.size(), offline.size());
  for (std::size_t i = 0; i < odometry.size(); ++i) EXPECT_LE(std::abs(odometry[i].t - offline[i].t), 1000) << i;  // tum: 9 decimals of s in a double
  const auto [run_dp, run_dq] = maxDifference(odometry, offline);
  std::cout << "DDS pipeline vs mcvio run: " << offline.size() << " poses, max difference " << run_dp << " m, " << run_dq
            << " rad\n";
  EXPECT_LT(run_dp, tolerance);
  EXPECT_LT(run_dq, tolerance);
}

}  // namespace

// End to end, the DDS pipeline and `mcvio run` agree to well under 1e-5 (measured 2026-12-01:
// 7.5e-10 m on the real excerpt, 7.7e-10 m on the moving sequence; text rounding of the TUM
// file); the estimator stage alone matches bit for bit (checked inside).
TEST(BackendComponent, LosslessPipelineOnTheRealExcerptGivesTheOfflineEstimatorsPoses) {
  const auto dir = excerptDir();
  if (dir.empty()) GTEST_SKIP() << "no ../shared/data/euroc_V1_01_excerpt";
  const auto odometry = runOverDdsAndCheckTheEstimatorStage(dir, 43);
  compareWithOfflineRun(dir, odometry, 1e-5);
}

TEST(BackendComponent, LosslessPipelineOnAMovingSimulatedSequenceGivesTheOfflineEstimatorsPoses) {
  const std::string dir = ::testing::TempDir() + "/backend_component_sim_" + std::to_string(getpid());
  components::test::writeCleanSequence(dir, 5, 4.0);
  const auto odometry = runOverDdsAndCheckTheEstimatorStage(dir, 47);
  compareWithOfflineRun(dir, odometry, 1e-5);
  std::filesystem::remove_all(dir);
}


TEST(BackendComponent, BadInputIsSkippedAndNoPoseComesBeforeInitialisation) {
  const auto dir = excerptDir();
  if (dir.empty()) GTEST_SKIP() << "no ../shared/data/euroc_V1_01_excerpt (calibration)";
  auto participant = mcvio::dds::Participant::create(testParticipantOptions(67));
  std::atomic<int> poses{0};
  auto listener = participant->createNode("listener");
  auto odom_sub = listener->createSubscription<Odometry>("/mcvio/odometry", mcvio::dds::QosProfile::lossless(),
                                                         [&](const Odometry&) { ++poses; });
  components::BackendComponentOptions bo;
  bo.calibration_dir = dir;
  bo.lossless = true;
  components::BackendComponent backend(participant->createNode("backend"), bo);
  auto pub = participant->createNode("source");
  auto imu = pub->createPublisher<sensor_msgs::msg::dds_::Imu_>("/imu0", mcvio::dds::QosProfile::lossless());
  auto features = pub->createPublisher<mcvio_msgs::msg::dds_::FeatureFrame_>("/mcvio/features", mcvio::dds::QosProfile::lossless());
  ASSERT_TRUE(imu->waitForReaders(1, 10s));
  ASSERT_TRUE(features->waitForReaders(1, 10s));

  const Timestamp t0 = 1000000000000;
  // Features before any IMU: they wait (lossless) and reach the estimator on flush.
  FeatureFrame early;
  early.t = t0;
  early.frame_index = 0;
  early.features.push_back({7, 0, {300, 200}, {0.1, -0.05}, TrackLabel::kUnknown});
  features->publish(components::toFeatureFrameMsg(early));
  ImuSample s;
  s.gyro = {0.001, 0.0, 0.0};
  s.accel = {0.0, 0.0, 9.81};
  for (int i = 1; i <= 40; ++i) {  // 0.2 s of IMU at 200 Hz: not enough to initialise
    s.t = t0 + i * 5000000;
    imu->publish(components::toImuMsg(s, "imu0"));
  }
  ImuSample nan = s;
  nan.t = s.t + 5000000;
  nan.accel.x() = NAN;
  imu->publish(components::toImuMsg(nan, "imu0"));
  ImuSample back = s;
  back.t = s.t - 1;
  imu->publish(components::toImuMsg(back, "imu0"));
  FeatureFrame empty;
  empty.t = t0 + 100000000;
  empty.frame_index = 1;
  features->publish(components::toFeatureFrameMsg(empty));
  FeatureFrame backwards = empty;
  backwards.t = empty.t - 1;
  backwards.frame_index = 2;
  features->publish(components::toFeatureFrameMsg(backwards));

  ASSERT_TRUE(waitUntil([&] { const auto st = backend.stats(); return st.imu_received == 42 && st.frames_received == 3; }, 20s));
  backend.flush();
  const auto st = backend.stats();
  EXPECT_EQ(st.imu_rejected, 2u);
  EXPECT_EQ(st.frames_rejected, 1u);
  EXPECT_EQ(st.frames_processed, 2u);
  EXPECT_EQ(st.poses_published, 0u);
  EXPECT_EQ(st.frames_not_accepted + st.not_initialized >= 2, true);
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(poses.load(), 0);
}

TEST(BackendComponent, OptionsAreValidated) {
  components::BackendComponentOptions o;
  EXPECT_THROW(o.validate(), std::invalid_argument);  // no calibration
  o.calibration_dir = "/nonexistent";
  EXPECT_NO_THROW(o.validate());
  o.body_frame = o.world_frame;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o.body_frame = "imu0";
  o.max_queued_frames = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o.max_queued_frames = 10;
  o.max_imu_wait_s = NAN;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

// Kalibr's imu.yaml naming the driver's IMU topic (rostopic) brings the backend onto it, and the
// IMU samples published there reach the estimator; a --remap rule for /imu0 still wins.
TEST(BackendComponent, ReadsTheImuTopicKalibrNamesUnlessRemapped) {
  const std::string dir = (std::filesystem::temp_directory_path() / ("mcvio_backend_kalibr_" + std::to_string(getpid()))).string();
  StereoRigCalibration rig = sim::eurocRigDefaults();
  rig.imu.topic = "/driver/imu";
  dataset::KalibrCalibration::write(rig, dir);
  auto participant = mcvio::dds::Participant::create(testParticipantOptions(73));
  components::BackendComponentOptions bo;
  bo.calibration_dir = dir;
  bo.lossless = true;
  auto node = participant->createNode("backend");
  components::BackendComponent backend(node, bo);
  EXPECT_EQ(node->resolveTopic("/imu0"), "/driver/imu");
  auto kept_node = participant->createNode("kept_backend", "/mcvio", TopicRemapping::parse({"/imu0:=/imu0"}));
  components::BackendComponent kept(kept_node, bo);
  EXPECT_EQ(kept_node->resolveTopic("/imu0"), "/imu0");

  auto pub = participant->createNode("driver");
  auto imu = pub->createPublisher<sensor_msgs::msg::dds_::Imu_>("/driver/imu", mcvio::dds::QosProfile::lossless());
  ASSERT_TRUE(imu->waitForReaders(1, 10s));
  ImuSample s;
  s.accel = {0, 0, 9.81};
  for (int i = 0; i < 5; ++i) {
    s.t = 1000000000 + i * 5000000;
    imu->publish(components::toImuMsg(s, "imu0"));
  }
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (std::chrono::steady_clock::now() < deadline && backend.stats().imu_received < 5) std::this_thread::sleep_for(20ms);
  EXPECT_EQ(backend.stats().imu_received, 5u);
  EXPECT_EQ(kept.stats().imu_received, 0u);
  std::filesystem::remove_all(dir);
}
