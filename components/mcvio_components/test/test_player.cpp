// The player publishes a small EuRoC folder in lossless mode: a reader of every topic receives
// every sample, with the data set's timestamps and the right frame ids.
#include <gtest/gtest.h>

#include <filesystem>
#include <mutex>
#include <set>
#include <unistd.h>

#include "mcvio/bag/bag_writer.hpp"
#include "mcvio/components/bag_player.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/dataset/euroc_writer.hpp"

using namespace mcvio;

namespace {

StereoRigCalibration smallRig() {
  StereoRigCalibration rig;
  for (int c = 0; c < 2; ++c) {
    auto& cam = rig.camera(c);
    cam.name = "cam" + std::to_string(c);
    cam.model = CameraModel(64, 48, {50, 50, 32, 24}, DistortionModel::kRadialTangential, {-0.1, 0.01, 0, 0});
    cam.T_BC.translation() = Eigen::Vector3d(0.11 * c, 0, 0);
  }
  return rig;
}

std::string writeSequence(int frames) {
  const std::string dir = ::testing::TempDir() + "/player_seq_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  dataset::EurocWriter w(dir, smallRig());
  const Timestamp t0 = 1403715273262142976;
  for (int i = 0; i < frames * 10; ++i) {
    ImuSample s;
    s.t = t0 + i * 5000000LL;
    s.accel = {0, 0, 9.81};
    s.gyro = {0, 0, 0.001 * i};
    w.addImu(s);
    if (i % 10 == 0) {
      cv::Mat a(48, 64, CV_8UC1, cv::Scalar(i % 255)), b(48, 64, CV_8UC1, cv::Scalar((i + 1) % 255));
      w.addStereoFrame(s.t, a, b);
      dataset::GroundTruthState g;
      g.t = s.t;
      g.p_WB = {0.01 * i, 0, 1};
      w.addGroundTruth(g);
    }
  }
  w.close();
  return dir;
}

}  // namespace

TEST(Player, LosslessDeliversEverySampleWithDatasetStampsAndFrameIds) {
  constexpr int kFrames = 30;
  const auto dir = writeSequence(kFrames);
  const auto data = dataset::EurocDataset::open(dir);
  ASSERT_EQ(data.stereoFrames().size(), static_cast<std::size_t>(kFrames));

  mcvio::dds::ParticipantOptions po;
  po.domain_id = 100 + static_cast<int>(getpid() % 100);
  auto participant = mcvio::dds::Participant::create(po);
  auto listener = participant->createNode("listener");
  std::mutex m;
  std::map<std::string, std::vector<Timestamp>> stamps;
  std::set<std::string> bad_frames;
  auto record = [&](const std::string& topic, const std_msgs::msg::dds_::Header_& h, const std::string& frame) {
    std::lock_guard<std::mutex> lock(m);
    stamps[topic].push_back(components::stampOf(h));
    if (h.frame_id() != frame) bad_frames.insert(topic + ":" + h.frame_id());
  };
  const auto qos = mcvio::dds::QosProfile::lossless();
  using namespace sensor_msgs::msg::dds_;
  auto s0 = listener->createSubscription<Image_>("/cam0/image_raw", qos, [&](const Image_& m) { record("/cam0/image_raw", m.header(), "cam0"); });
  auto s1 = listener->createSubscription<Image_>("/cam1/image_raw", qos, [&](const Image_& m) { record("/cam1/image_raw", m.header(), "cam1"); });
  auto s2 = listener->createSubscription<CameraInfo_>("/cam0/camera_info", qos, [&](const CameraInfo_& m) { record("/cam0/camera_info", m.header(), "cam0"); });
  auto s3 = listener->createSubscription<CameraInfo_>("/cam1/camera_info", qos, [&](const CameraInfo_& m) { record("/cam1/camera_info", m.header(), "cam1"); });
  auto s4 = listener->createSubscription<Imu_>("/imu0", qos, [&](const Imu_& m) { record("/imu0", m.header(), "imu0"); });
  auto s5 = listener->createSubscription<nav_msgs::msg::dds_::Odometry_>(
      "/ground_truth/odometry", qos, [&](const nav_msgs::msg::dds_::Odometry_& m) { record("/ground_truth/odometry", m.header(), "world"); });

  auto player_participant = mcvio::dds::Participant::create(po);
  components::PlayerOptions opts;
  opts.lossless = true;
  opts.progress = false;
  components::Player player(player_participant->createNode("player"), data, opts);
  const auto summary = player.run();
  EXPECT_EQ(summary.frames, static_cast<std::size_t>(kFrames));
  EXPECT_EQ(summary.imu_samples, data.imu().size());

  std::lock_guard<std::mutex> lock(m);
  EXPECT_TRUE(bad_frames.empty()) << *bad_frames.begin();
  std::vector<Timestamp> frame_times, imu_times;
  for (const auto& f : data.stereoFrames()) frame_times.push_back(f.t);
  for (const auto& s : data.imu()) imu_times.push_back(s.t);
  for (const char* t : {"/cam0/image_raw", "/cam1/image_raw", "/cam0/camera_info", "/cam1/camera_info"}) {
    EXPECT_EQ(stamps[t], frame_times) << t;
  }
  EXPECT_EQ(stamps["/imu0"], imu_times);
  EXPECT_EQ(stamps["/ground_truth/odometry"].size(), data.groundTruth().size());
  std::filesystem::remove_all(dir);
}

TEST(Player, LosslessWithoutReadersFailsClearly) {
  const auto dir = writeSequence(2);
  const auto data = dataset::EurocDataset::open(dir);
  mcvio::dds::ParticipantOptions po;
  po.domain_id = 100 + static_cast<int>((getpid() + 50) % 100);
  auto participant = mcvio::dds::Participant::create(po);
  components::PlayerOptions opts;
  opts.lossless = true;
  opts.progress = false;
  opts.wait_for_readers_s = 0.3;
  components::Player player(participant->createNode("player"), data, opts);
  try {
    player.run();
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no reader of /cam0/image_raw"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(Player, BadOptionsAreRejected) {
  components::PlayerOptions o;
  o.rate = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o.rate = 1;
  o.start_s = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

// A bag message with an empty payload (a damaged bag, or a foreign writer) used to make a lossless
// playback retry it for 60 s and then blame the reader: it is an error naming file, topic and time.
TEST(BagPlayer, PayloadWithoutCdrHeaderIsAnInputError) {
  const std::string dir = ::testing::TempDir() + "/player_empty_payload_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  {
    bag::BagWriterOptions o;
    o.storage = "sqlite3";
    bag::BagWriter w(dir, o);
    bag::TopicInfo t;
    t.name = "/chatter";
    t.type = "std_msgs/msg/String";
    t.message_definition = "string data\n";
    w.addTopic(t);
    const std::vector<std::uint8_t> hello = {0, 1, 0, 0, 3, 0, 0, 0, 'h', 'i', 0, 0};
    w.write("/chatter", 1000, 1000, hello.data(), hello.size());
    w.write("/chatter", 2000, 2000, hello.data(), 0);
  }
  mcvio::dds::ParticipantOptions po;
  po.domain_id = 100 + static_cast<int>((getpid() + 31) % 100);
  auto participant = mcvio::dds::Participant::create(po);
  components::PlayerOptions opts;
  opts.lossless = true;
  opts.progress = false;
  opts.min_readers = 0;
  components::BagPlayer player(participant->createNode("player"), dir, opts);
  const auto start = std::chrono::steady_clock::now();
  try {
    player.run();
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(dir), std::string::npos) << what;
    EXPECT_NE(what.find("topic /chatter"), std::string::npos) << what;
    EXPECT_NE(what.find("log time 2000 ns"), std::string::npos) << what;
    EXPECT_NE(what.find("no CDR header"), std::string::npos) << what;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
  std::filesystem::remove_all(dir);
}
