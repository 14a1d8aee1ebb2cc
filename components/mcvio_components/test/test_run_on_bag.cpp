// A bag recorded from a lossless playback of the real excerpt runs through `mcvio run` to the
// same trajectory as the EuRoC folder itself: what went over DDS is what the offline run sees.
// So does a driver's bag of compressed images on its own topic names (remapped, or named by
// Kalibr's rostopic).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>
#include <unistd.h>

#include <fastdds/rtps/common/SerializedPayload.h>
#include <opencv2/imgcodecs.hpp>

#include "mcvio/bag/bag_metadata.hpp"
#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/bag/bag_writer.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/components/recorder.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/dataset/kalibr_calibration.hpp"
#include "mcvio/interfaces/message_registry.hpp"
#include "mcvio/pipeline/offline_run.hpp"
#include "component_test_support.hpp"

using namespace mcvio;

namespace {

std::vector<std::string> lines(const std::string& path) {
  std::vector<std::string> v;
  std::ifstream in(path);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

// Copies the topics `keep` accepts, with their messages, into a new bag; `edit` may change each
// topic's description on the way.
template <typename Keep, typename Edit>
void copyBag(const std::string& from, const std::string& to, const bag::BagWriterOptions& options, Keep keep, Edit edit) {
  bag::BagReader in(from);
  bag::BagWriter out(to, options);
  for (auto t : in.topics()) {
    if (!keep(t.name)) continue;
    edit(t);
    out.addTopic(t);
  }
  for (bag::BagMessage m; in.next(m);)
    if (keep(m.topic)) out.write(m);
  out.close();
}

// The InputError a run ends with, or "ran" when it does not fail.
std::string inputErrorOf(const pipeline::OfflineRunOptions& options) {
  try {
    pipeline::runOffline(options);
    return "ran";
  } catch (const InputError& e) {
    return e.what();
  }
}

}  // namespace

TEST(RunOnBag, RecordedPlaybackGivesTheSameTrajectoryAsTheDataset) {
  const std::string dir = components::test::excerptDir();
  if (dir.empty()) GTEST_SKIP() << "no ../shared/data/euroc_V1_01_excerpt";
  const std::string base = ::testing::TempDir() + "/run_on_bag_" + std::to_string(getpid());
  std::filesystem::remove_all(base);
  const auto data = dataset::EurocDataset::open(dir);

  const auto po = components::test::testParticipantOptions(73);
  mcvio::dds::GraphMonitor monitor;
  auto rec_participant = mcvio::dds::Participant::create(po, &monitor);
  components::RecorderOptions ro;
  ro.topics = {"/cam0/image_raw", "/cam1/image_raw", "/imu0"};
  ro.bag.compression = bag::Compression::Lz4;
  components::Recorder recorder(rec_participant->createNode("recorder"), monitor, base + "/bag", ro);
  recorder.start();
  auto play_participant = mcvio::dds::Participant::create(po);
  components::PlayerOptions opts;
  opts.lossless = true;
  opts.progress = false;
  opts.min_readers = 0;  // only the recorded topics have readers; wait for those below
  opts.duration_s = 4.7;
  components::Player player(play_participant->createNode("player"), data, opts);
  // Let the recorder discover and subscribe before playing.
  ASSERT_TRUE(monitor.waitFor([](const auto& topics) {
    int n = 0;
    for (const auto& t : topics) n += (t.name == "/imu0" || t.name == "/cam0/image_raw" || t.name == "/cam1/image_raw") && t.subscribers > 0;
    return n == 3;
  }, std::chrono::seconds(20)));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  player.run();
  recorder.stop();

  pipeline::OfflineRunOptions from_bag;
  from_bag.dataset_dir = base + "/bag";
  from_bag.calibration_dir = dir;
  from_bag.output_dir = base + "/from_bag";
  from_bag.progress = false;
  const auto a = pipeline::runOffline(from_bag);
  pipeline::OfflineRunOptions from_dataset = from_bag;
  from_dataset.dataset_dir = dir;
  from_dataset.output_dir = base + "/from_dataset";
  const auto b = pipeline::runOffline(from_dataset);
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_EQ(a.estimated, b.estimated);
  // Same poses (the estimator is bit-reproducible; the tolerance below also absorbs the TUM files'
  // nine decimals).
  const auto la = lines(base + "/from_bag/trajectory.tum"), lb = lines(base + "/from_dataset/trajectory.tum");
  ASSERT_EQ(la.size(), lb.size());
  double max_diff = 0;
  for (std::size_t i = 1; i < la.size(); ++i) {
    std::istringstream sa(la[i]), sb(lb[i]);
    for (int k = 0; k < 8; ++k) {
      double x, y;
      sa >> x;
      sb >> y;
      max_diff = std::max(max_diff, std::abs(x - y));
    }
  }
  EXPECT_LT(max_diff, 1e-6);

  // The same messages in an sqlite3 bag whose topics carry no message definition (rosbag2 before
  // Iron has no message_definitions table): without definitions the run names the type; with the
  // built-in ones `mcvio run` passes it gives the same trajectory and says what it did.
  bag::BagWriterOptions sqlite;
  sqlite.storage = "sqlite3";
  copyBag(base + "/bag", base + "/before_iron", sqlite, [](const std::string&) { return true; },
          [](bag::TopicInfo& t) { t.message_definition.clear(); });
  pipeline::OfflineRunOptions before_iron = from_bag;
  before_iron.dataset_dir = base + "/before_iron";
  before_iron.output_dir = base + "/from_before_iron";
  const std::string no_definitions = inputErrorOf(before_iron);
  EXPECT_NE(no_definitions.find("has no message definition in the bag"), std::string::npos) << no_definitions;
  for (const auto& d : interfaces::MessageRegistry::all())
    before_iron.known_message_definitions.emplace(std::string(d.name), std::string(d.full_definition));
  const auto c = pipeline::runOffline(before_iron);
  EXPECT_EQ(c.estimated, a.estimated);
  EXPECT_EQ(lines(base + "/from_before_iron/trajectory.tum"), la);
  std::ifstream before_iron_stats(before_iron.output_dir + "/stats.json");
  const std::string before_iron_json{std::istreambuf_iterator<char>(before_iron_stats), std::istreambuf_iterator<char>()};
  EXPECT_NE(before_iron_json.find("read with the built-in sensor_msgs/msg/Imu"), std::string::npos) << before_iron_json;

  // What the bag reader warns about (here metadata.yaml's type of /imu0 against the storage's)
  // reaches the run's warnings and stats.json, as `mcvio play` prints it.
  auto meta = bag::readBagMetadata(base + "/bag");
  for (auto& t : meta.topics_with_message_count) {
    if (t.topic.name == "/imu0") t.topic.type = "sensor_msgs/msg/MagneticField";
  }
  bag::writeBagMetadata(base + "/bag", meta);
  from_bag.output_dir = base + "/from_bag_warned";
  pipeline::runOffline(from_bag);
  std::ifstream stats(from_bag.output_dir + "/stats.json");
  const std::string json{std::istreambuf_iterator<char>(stats), std::istreambuf_iterator<char>()};
  EXPECT_NE(json.find("topic /imu0: metadata.yaml says sensor_msgs/msg/MagneticField"), std::string::npos) << json;

  // A bag without the images (as `mcvio demo` records the backend's input): the error names the
  // missing topic and what the bag holds instead.
  copyBag(base + "/bag", base + "/imu_only", bag::BagWriterOptions{}, [](const std::string& topic) { return topic == "/imu0"; },
          [](bag::TopicInfo&) {});
  pipeline::OfflineRunOptions imu_only = from_bag;
  imu_only.dataset_dir = base + "/imu_only";
  imu_only.output_dir = base + "/from_imu_only";
  const std::string no_images = inputErrorOf(imu_only);
  EXPECT_NE(no_images.find("the bag has no /cam0/image_raw (it holds /imu0)"), std::string::npos) << no_images;

  // /mcvio/features of another type, or of our type name with another definition (here the IMU's
  // messages under either), is refused by name, not decoded as something else.
  const auto imuAsFeatures = [&](const std::string& dir, const std::string& type) {
    bag::BagReader in(base + "/bag");
    bag::BagWriter out(dir);
    for (auto t : in.topics()) {
      if (t.name != "/imu0") continue;
      out.addTopic(t);
      t.name = "/mcvio/features";
      t.type = type;
      out.addTopic(t);
    }
    for (bag::BagMessage m; in.next(m);) {
      if (m.topic != "/imu0") continue;
      out.write(m);
      m.topic = "/mcvio/features";
      out.write(m);
    }
    out.close();
    pipeline::OfflineRunOptions o = from_bag;
    o.dataset_dir = dir;
    o.output_dir = dir + "_run";
    return inputErrorOf(o);
  };
  const std::string wrong_type = imuAsFeatures(base + "/wrong_type", "sensor_msgs/msg/Imu");
  EXPECT_NE(wrong_type.find("topic /mcvio/features has type sensor_msgs/msg/Imu, not mcvio_msgs/msg/FeatureFrame"),
            std::string::npos)
      << wrong_type;
  const std::string wrong_definition = imuAsFeatures(base + "/wrong_definition", "mcvio_msgs/msg/FeatureFrame");
  EXPECT_NE(wrong_definition.find("/mcvio/features"), std::string::npos) << wrong_definition;
  EXPECT_NE(wrong_definition.find("not this version's mcvio_msgs/msg/FeatureFrame: no field 'frame_index'"), std::string::npos)
      << wrong_definition;

  from_bag.calibration_dir.clear();
  EXPECT_THROW(pipeline::runOffline(from_bag), InputError);
  std::filesystem::remove_all(base);
}

namespace {

// The CDR payload of a generated message, as a recorder stores it.
template <class T>
std::vector<std::uint8_t> payloadOf(const T& msg) {
  typename interfaces::RosType<T>::PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(const_cast<T*>(&msg))());
  EXPECT_TRUE(type.serialize(const_cast<T*>(&msg), &payload));
  return {payload.data, payload.data + payload.length};
}

// A bag topic of a built-in type, described as a recorder describes it.
bag::TopicInfo topicOf(const std::string& name, const std::string& type) {
  const auto* d = interfaces::MessageRegistry::find(type);
  bag::TopicInfo t;
  t.name = name;
  t.type = type;
  t.message_definition = std::string(d->full_definition);
  t.type_description_hash = std::string(d->type_hash);
  return t;
}

}  // namespace

// A driver's bag with its own topic names and image_transport's compressed images (png, so
// lossless) runs like the EuRoC folder it was made from; a frame that does not decode costs
// that frame, with a warning naming the bag, topic and time.
TEST(RunOnBag, CompressedImagesOnADriversTopicsGiveTheEurocTrajectory) {
  using CompressedImage = sensor_msgs::msg::dds_::CompressedImage_;
  const std::string base = ::testing::TempDir() + "/run_on_compressed_" + std::to_string(getpid());
  std::filesystem::remove_all(base);
  components::test::writeCleanSequence(base + "/seq", 5, 3.0);
  const auto data = dataset::EurocDataset::open(base + "/seq");
  const auto writeBag = [&](const std::string& dir, std::size_t damaged_frame) {
    bag::BagWriter out(dir);
    const auto put = [&out](const std::string& topic, Timestamp t, const std::vector<std::uint8_t>& bytes) {
      out.write(topic, t, t, bytes.data(), bytes.size());
    };
    const char* image_topics[2] = {"/stereo/left/image_raw/compressed", "/stereo/right/image_raw/compressed"};
    for (const char* t : image_topics) out.addTopic(topicOf(t, "sensor_msgs/msg/CompressedImage"));
    out.addTopic(topicOf("/stereo/imu", "sensor_msgs/msg/Imu"));
    std::size_t next_imu = 0;
    for (std::size_t i = 0; i < data.stereoFrames().size(); ++i) {
      const auto& f = data.stereoFrames()[i];
      for (; next_imu < data.imu().size() && data.imu()[next_imu].t <= f.t; ++next_imu)
        put("/stereo/imu", data.imu()[next_imu].t, payloadOf(components::toImuMsg(data.imu()[next_imu], "imu")));
      for (int c = 0; c < 2; ++c) {
        cv::Mat grey;
        std::string error;
        ASSERT_TRUE(data.tryLoadImage(f, c, &grey, &error)) << error;
        CompressedImage msg;
        msg.header(components::toImageMsg(grey, f.t, c == 0 ? "left" : "right").header());
        msg.format(c == 0 ? "mono8; png compressed mono8" : "png");
        std::vector<std::uint8_t> png;
        cv::imencode(".png", grey, png);
        if (i == damaged_frame && c == 0) png.resize(png.size() / 2);
        msg.data(png);
        put(image_topics[c], f.t, payloadOf(msg));
      }
    }
    for (; next_imu < data.imu().size(); ++next_imu)
      put("/stereo/imu", data.imu()[next_imu].t, payloadOf(components::toImuMsg(data.imu()[next_imu], "imu")));
    out.close();
  };
  writeBag(base + "/bag", std::size_t(-1));
  writeBag(base + "/damaged", 30);

  pipeline::OfflineRunOptions euroc;
  euroc.dataset_dir = base + "/seq";
  euroc.output_dir = base + "/from_euroc";
  euroc.progress = false;
  const auto a = pipeline::runOffline(euroc);
  pipeline::OfflineRunOptions from_bag = euroc;
  from_bag.dataset_dir = base + "/bag";
  from_bag.calibration_dir = base + "/seq";
  from_bag.output_dir = base + "/from_bag";
  EXPECT_NE(inputErrorOf(from_bag).find("the bag has no /cam0/image_raw"), std::string::npos);
  from_bag.remapping = TopicRemapping::parse({"/cam0/image_raw:=/stereo/left/image_raw/compressed",
                                              "/cam1/image_raw:=/stereo/right/image_raw/compressed", "/imu0:=/stereo/imu"});
  const auto b = pipeline::runOffline(from_bag);
  EXPECT_GT(a.estimated, 30u);
  EXPECT_EQ(b.estimated, a.estimated);
  EXPECT_EQ(b.skipped, 0u);
  EXPECT_EQ(lines(base + "/from_bag/trajectory.tum"), lines(base + "/from_euroc/trajectory.tum"));

  // Kalibr's files naming the driver's topics (rostopic) choose them without --remap, as the
  // same rules given by hand do; a --remap rule for a sensor still wins.
  StereoRigCalibration rig = data.calibration();
  rig.cam0.topic = "/stereo/left/image_raw/compressed";
  rig.cam1.topic = "/stereo/right/image_raw/compressed";
  rig.imu.topic = "/stereo/imu";
  dataset::KalibrCalibration::write(rig, base + "/kalibr");
  pipeline::OfflineRunOptions kalibr = from_bag;
  kalibr.calibration_dir = base + "/kalibr";
  kalibr.output_dir = base + "/from_kalibr_remapped";
  const auto by_hand = pipeline::runOffline(kalibr);
  kalibr.remapping = {};
  kalibr.output_dir = base + "/from_kalibr";
  const auto by_rostopic = pipeline::runOffline(kalibr);
  EXPECT_EQ(by_rostopic.estimated, by_hand.estimated);
  EXPECT_GT(by_rostopic.estimated, 30u);
  EXPECT_EQ(lines(base + "/from_kalibr/trajectory.tum"), lines(base + "/from_kalibr_remapped/trajectory.tum"));
  kalibr.remapping = TopicRemapping::parse({"/imu0:=/imu0"});
  EXPECT_NE(inputErrorOf(kalibr).find("the bag has no /imu0"), std::string::npos) << inputErrorOf(kalibr);

  pipeline::OfflineRunOptions damaged = from_bag;
  damaged.dataset_dir = base + "/damaged";
  damaged.output_dir = base + "/from_damaged";
  const auto c = pipeline::runOffline(damaged);
  EXPECT_EQ(c.frames + 1, a.frames);
  std::ifstream stats(damaged.output_dir + "/stats.json");
  const std::string json{std::istreambuf_iterator<char>(stats), std::istreambuf_iterator<char>()};
  EXPECT_NE(json.find("/stereo/left/image_raw/compressed"), std::string::npos) << json;
  EXPECT_NE(json.find("does not decode; skipped"), std::string::npos) << json;
  std::filesystem::remove_all(base);
}
