// The player publishes a small EuRoC folder in lossless mode: a reader of every topic receives
// every sample, with the data set's timestamps and the right frame ids.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <set>
#include <unistd.h>

#include "mcvio/bag/bag_writer.hpp"
#include "mcvio/components/bag_player.hpp"
#include "mcvio/components/playback_pacer.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/dataset/euroc_writer.hpp"
#include "component_test_support.hpp"

using namespace mcvio;

namespace {

/// A participant on a test domain of its own (per process, per test): parallel test runs must
/// not hear each other.
std::shared_ptr<mcvio::dds::Participant> testParticipant(int salt) {
  return mcvio::dds::Participant::create(components::test::testParticipantOptions(salt));
}

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

  auto participant = testParticipant(0);
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

  auto player_participant = testParticipant(0);  // the listener's domain
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
  auto participant = testParticipant(50);
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
  auto participant = testParticipant(31);
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

// Paced playback sleeps until (t - t_first) / rate; a gap longer than max_gap_s counts as max_gap_s.
TEST(PlaybackPacer, RegularStampsKeepTheirScheduleAndOnlyLongGapsAreShortened) {
  using std::chrono::nanoseconds;
  const Timestamp t0 = 1403715273262142976;
  components::PlaybackPacer regular(t0, 2.0, 10.0);
  for (int i = 0; i < 50; ++i) {
    const auto s = regular.next(t0 + i * 5000000LL);  // 200 Hz
    EXPECT_EQ(s.wall_offset, nanoseconds(i * 2500000LL)) << i;
    EXPECT_EQ(s.skipped_s, 0.0);
    EXPECT_FALSE(s.backwards);
  }
  // A 1e6 s jump plays 10 s (data) after the previous message; what follows keeps its spacing.
  components::PlaybackPacer gap(t0, 1.0, 10.0);
  EXPECT_EQ(gap.next(t0).wall_offset, nanoseconds(0));
  EXPECT_EQ(gap.next(t0 + 1000000000LL).wall_offset, nanoseconds(1000000000LL));
  const auto far = gap.next(t0 + 1000000000LL + fromSeconds(1e6));
  EXPECT_EQ(far.wall_offset, nanoseconds(11000000000LL));
  EXPECT_NEAR(far.gap_s, 1e6, 1e-6);
  EXPECT_NEAR(far.skipped_s, 1e6 - 10, 1e-6);
  EXPECT_EQ(gap.next(t0 + 1500000000LL + fromSeconds(1e6)).wall_offset, nanoseconds(11500000000LL));
  // Exactly the limit is kept; 0 keeps every gap.
  components::PlaybackPacer at_limit(t0, 1.0, 10.0);
  EXPECT_EQ(at_limit.next(t0 + 10000000000LL).skipped_s, 0.0);
  components::PlaybackPacer never(t0, 1.0, 0.0);
  EXPECT_EQ(never.next(t0 + fromSeconds(3600)).wall_offset, nanoseconds(fromSeconds(3600)));
}

// A stamp earlier than the previous one (neither player yields one today: the bag reader and the
// data set player sort by time) goes out at once, and does not make the next message a "gap".
TEST(PlaybackPacer, BackwardsStampPlaysAtOnceWithoutNegativeSleep) {
  using std::chrono::nanoseconds;
  const Timestamp t0 = 1000000000000;
  components::PlaybackPacer p(t0, 1.0, 5.0);
  EXPECT_EQ(p.next(t0 + 2000000000LL).wall_offset, nanoseconds(2000000000LL));
  const auto back = p.next(t0 - fromSeconds(1e6));
  EXPECT_TRUE(back.backwards);
  EXPECT_EQ(back.wall_offset, nanoseconds(2000000000LL));  // the previous message's time: no wait
  EXPECT_NE(components::PlaybackPacer::describe(back, 5.0).find("played at once"), std::string::npos);
  const auto after = p.next(t0 + 3000000000LL);
  EXPECT_FALSE(after.backwards);
  EXPECT_EQ(after.skipped_s, 0.0);
  EXPECT_EQ(after.wall_offset, nanoseconds(3000000000LL));
}

TEST(Player, MaxGapMustBeANonNegativeNumber) {
  components::PlayerOptions o;
  EXPECT_GT(o.max_gap_s, 0.0);
  for (double bad : {-1.0, -1e-9, std::nan("")}) {
    o.max_gap_s = bad;
    try {
      o.validate();
      FAIL() << "accepted max_gap_s " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("max_gap_s"), std::string::npos) << e.what();
    }
  }
  for (double good : {0.0, 0.5, HUGE_VAL}) {
    o.max_gap_s = good;
    EXPECT_NO_THROW(o.validate()) << good;
  }
}

namespace {

// /chatter at 0, 0.1, 0.2 s and, when `far_s` > 0, /late that long after the last one.
std::string writeChatterBag(const std::string& name, double far_s) {
  const std::string dir = ::testing::TempDir() + "/" + name + "_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  bag::BagWriterOptions o;
  o.storage = "sqlite3";
  bag::BagWriter w(dir, o);
  for (const char* topic : {"/chatter", "/late"}) {
    bag::TopicInfo t;
    t.name = topic;
    t.type = "std_msgs/msg/String";
    t.message_definition = "string data\n";
    w.addTopic(t);
  }
  const std::vector<std::uint8_t> hi = {0, 1, 0, 0, 3, 0, 0, 0, 'h', 'i', 0, 0};
  const Timestamp t0 = 1700000000000000000;
  for (int i = 0; i < 3; ++i) w.write("/chatter", t0 + i * 100000000LL, t0 + i * 100000000LL, hi.data(), hi.size());
  if (far_s > 0) w.write("/late", t0 + 200000000LL + fromSeconds(far_s), t0, hi.data(), hi.size());
  return dir;
}

components::PlaybackSummary playPaced(const std::string& dir, double max_gap_s, int domain_offset, std::string* err) {
  auto participant = testParticipant(domain_offset);
  components::PlayerOptions opts;
  opts.progress = false;
  opts.min_readers = 0;
  opts.max_gap_s = max_gap_s;
  components::BagPlayer player(participant->createNode("player"), dir, opts);
  ::testing::internal::CaptureStderr();
  const auto s = player.run();
  *err = ::testing::internal::GetCapturedStderr();
  return s;
}

}  // namespace

// One message 1e6 s after the rest (a damaged or hand-edited bag) used to make paced playback
// sleep for 11 days without a word: the gap is played as max_gap_s, with a warning naming it.
TEST(BagPlayer, FarFutureMessageIsNotSleptThrough) {
  const auto dir = writeChatterBag("player_far_future", 1e6);
  std::string err;
  const auto start = std::chrono::steady_clock::now();
  const auto s = playPaced(dir, 0.5, 37, &err);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(wall_s, 10.0);
  EXPECT_GE(wall_s, 0.2 + 0.5);  // the original spacing and the limit are still waited for
  EXPECT_EQ(s.messages, 4u);
  EXPECT_EQ(s.shortened_gaps, 1u);
  EXPECT_NEAR(s.skipped_gap_seconds, 1e6 - 0.5, 1e-3);
  EXPECT_NE(err.find("warning"), std::string::npos) << err;
  EXPECT_NE(err.find(dir), std::string::npos) << err;
  EXPECT_NE(err.find("topic /late"), std::string::npos) << err;
  EXPECT_NE(err.find("message 4 of 4"), std::string::npos) << err;
  EXPECT_NE(err.find("1000000.000 s after the previous message"), std::string::npos) << err;
  EXPECT_EQ(err.find("/chatter"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}

TEST(BagPlayer, BagWithoutLongGapsKeepsItsTimingAndSaysNothing) {
  const auto dir = writeChatterBag("player_no_gap", 0);
  std::string err;
  const auto start = std::chrono::steady_clock::now();
  const auto s = playPaced(dir, components::PlayerOptions().max_gap_s, 41, &err);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(wall_s, 0.2);
  EXPECT_EQ(s.messages, 3u);
  EXPECT_EQ(s.shortened_gaps, 0u);
  EXPECT_EQ(err.find("warning"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}

// The data set player shares the schedule: an IMU sample 1e6 s after the rest is played 0.5 s
// after the previous event, with a warning naming the folder and topic.
TEST(Player, FarFutureImuSampleIsNotSleptThrough) {
  const std::string dir = ::testing::TempDir() + "/player_far_imu_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  {
    dataset::EurocWriter w(dir, smallRig());
    const Timestamp t0 = 1403715273262142976;
    for (int i = 0; i < 11; ++i) {
      ImuSample s;
      s.t = t0 + i * 5000000LL + (i == 10 ? fromSeconds(1e6) : 0);
      s.accel = {0, 0, 9.81};
      w.addImu(s);
      if (i == 0) {
        cv::Mat a(48, 64, CV_8UC1, cv::Scalar(10));
        w.addStereoFrame(s.t, a, a);
      }
    }
    w.close();
  }
  const auto data = dataset::EurocDataset::open(dir);
  auto participant = testParticipant(43);
  components::PlayerOptions opts;
  opts.progress = false;
  opts.min_readers = 0;
  opts.max_gap_s = 0.5;
  components::Player player(participant->createNode("player"), data, opts);
  const auto start = std::chrono::steady_clock::now();
  ::testing::internal::CaptureStderr();
  const auto s = player.run();
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
  EXPECT_EQ(s.imu_samples, 11u);
  EXPECT_EQ(s.shortened_gaps, 1u);
  EXPECT_NE(err.find("player_far_imu_" + std::to_string(getpid())), std::string::npos) << err;
  EXPECT_NE(err.find("topic /imu0"), std::string::npos) << err;
  EXPECT_NE(err.find("played 0.5 s after it"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}
