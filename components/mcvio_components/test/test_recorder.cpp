// Record while the player plays a sequence losslessly: every topic's message count matches and
// every payload is byte-identical to what the player serialised; our reader reads the bag back.
#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/components/recorder.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/dataset/euroc_writer.hpp"
#include "component_test_support.hpp"

using namespace mcvio;

namespace {

template <class T>
std::vector<std::uint8_t> serialize(T msg) {
  typename interfaces::RosType<T>::PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t p(type.getSerializedSizeProvider(&msg)());
  type.serialize(&msg, &p);
  return std::vector<std::uint8_t>(p.data, p.data + p.length);
}

std::string writeSequence(const std::string& dir, int frames) {
  std::filesystem::remove_all(dir);
  StereoRigCalibration rig;
  for (int c = 0; c < 2; ++c) {
    rig.camera(c).name = "cam" + std::to_string(c);
    rig.camera(c).model = CameraModel(64, 48, {50, 50, 32, 24}, DistortionModel::kRadialTangential, {-0.1, 0.01, 0, 0});
  }
  dataset::EurocWriter w(dir, rig);
  const Timestamp t0 = 1403715273262142976;
  for (int i = 0; i < frames * 10; ++i) {
    ImuSample s;
    s.t = t0 + i * 5000000LL;
    s.accel = {0.01 * i, 0, 9.81};
    w.addImu(s);
    if (i % 10 == 0) {
      cv::Mat a(48, 64, CV_8UC1), b(48, 64, CV_8UC1);
      cv::randu(a, 0, 255);
      cv::randu(b, 0, 255);
      w.addStereoFrame(s.t, a, b);
    }
  }
  w.close();
  return dir;
}

}  // namespace

class RecorderTest : public ::testing::TestWithParam<std::string> {};

TEST_P(RecorderTest, RecordsEveryMessageOfALosslessPlaybackByteForByte) {
  const std::string base = ::testing::TempDir() + "/recorder_" + std::to_string(getpid()) + GetParam();
  const auto data = dataset::EurocDataset::open(writeSequence(base + "_seq", 25));
  const auto po = components::test::testParticipantOptions(17);

  mcvio::dds::GraphMonitor monitor;
  auto rec_participant = mcvio::dds::Participant::create(po, &monitor);
  components::RecorderOptions ro;
  ro.all = true;
  ro.bag.storage = GetParam();
  ro.bag.chunk_size = 64 * 1024;
  const std::string bag_dir = base + "_bag";
  std::filesystem::remove_all(bag_dir);
  components::Recorder recorder(rec_participant->createNode("recorder"), monitor, bag_dir, ro);
  recorder.start();

  auto play_participant = mcvio::dds::Participant::create(po);
  components::PlayerOptions opts;
  opts.lossless = true;
  opts.progress = false;
  opts.wait_for_readers_s = 20;
  components::Player player(play_participant->createNode("player"), data, opts);
  player.run();
  const auto summary = recorder.stop();

  // What the player sent, serialised the same way.
  std::map<std::string, std::vector<std::vector<std::uint8_t>>> expected;
  for (const auto& f : data.stereoFrames()) {
    for (int c = 0; c < 2; ++c) {
      const std::string cam = "/cam" + std::to_string(c);
      expected[cam + "/camera_info"].push_back(serialize(components::toCameraInfoMsg(data.calibration().camera(c), f.t)));
      expected[cam + "/image_raw"].push_back(serialize(components::toImageMsg(data.loadImage(f, c), f.t, "cam" + std::to_string(c))));
    }
  }
  for (const auto& s : data.imu()) expected["/imu0"].push_back(serialize(components::toImuMsg(s, "imu0")));

  std::map<std::string, std::vector<std::vector<std::uint8_t>>> recorded;
  std::map<std::string, std::vector<Timestamp>> publish_times;
  bag::BagReader reader(bag_dir);
  bag::BagMessage m;
  while (reader.next(m)) {
    recorded[m.topic].push_back(m.data);
    publish_times[m.topic].push_back(m.publish_time);
  }
  // Publish time is the header stamp: the data set's own time (MCAP; rosbag2's sqlite3 schema
  // has only the receive time).
  if (GetParam() == "mcap") {
    ASSERT_EQ(publish_times["/imu0"].size(), data.imu().size());
    for (std::size_t i = 0; i < data.imu().size(); ++i) EXPECT_EQ(publish_times["/imu0"][i], data.imu()[i].t);
  }
  ASSERT_EQ(recorded.size(), expected.size());
  for (const auto& [topic, msgs] : expected) {
    ASSERT_EQ(recorded[topic].size(), msgs.size()) << topic;
    EXPECT_EQ(summary.messages_per_topic.at(topic), msgs.size()) << topic;
    for (std::size_t i = 0; i < msgs.size(); ++i) EXPECT_EQ(recorded[topic][i], msgs[i]) << topic << " #" << i;
  }
  for (const auto& t : reader.topics()) {
    EXPECT_FALSE(t.message_definition.empty()) << t.name;
    EXPECT_EQ(t.type_description_hash.substr(0, 7), "RIHS01_") << t.name;
    EXPECT_NE(t.offered_qos_profiles.find("reliability: 1"), std::string::npos) << t.offered_qos_profiles;
  }
  std::filesystem::remove_all(bag_dir);
  std::filesystem::remove_all(base + "_seq");
}

INSTANTIATE_TEST_SUITE_P(Storages, RecorderTest, ::testing::Values("mcap", "sqlite3"));

TEST(Recorder, NothingSelectedOrBadRegexIsRejected) {
  components::RecorderOptions o;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o.regex = "([";
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o.regex = "^/cam";
  EXPECT_NO_THROW(o.validate());
}
