#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <thread>
#include <unistd.h>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dds/generic_subscription.hpp"
#include "mcvio/dds/graph_monitor.hpp"
#include "mcvio/dds/node.hpp"

using namespace mcvio::dds;
using namespace std::chrono_literals;
using Image = sensor_msgs::msg::dds_::Image_;
using Imu = sensor_msgs::msg::dds_::Imu_;

namespace {

// A domain per test process keeps parallel ctest runs apart.
ParticipantOptions testOptions() {
  ParticipantOptions o;
  o.domain_id = 100 + static_cast<int>(getpid() % 100);
  return o;
}

template <class Pred>
bool eventually(Pred pred, std::chrono::milliseconds timeout = 10s) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!pred()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(5ms);
  }
  return true;
}

Image makeImage(std::uint32_t seq) {
  Image img;
  img.header().stamp().sec(1403715273);
  img.header().stamp().nanosec(seq);
  img.header().frame_id("cam0");
  img.height(480);
  img.width(752);
  img.encoding("mono8");
  img.step(752);
  img.data().resize(752 * 480);
  for (std::size_t i = 0; i < img.data().size(); ++i) img.data()[i] = static_cast<std::uint8_t>(i + seq);
  return img;
}

}  // namespace

TEST(Participant, BadOptionsAreRejectedWithTheirReason) {
  ParticipantOptions o = testOptions();
  o.domain_id = 233;
  try {
    Participant::create(o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("domain id 233"), std::string::npos) << e.what();
  }
  o.domain_id = -1;
  EXPECT_THROW(Participant::create(o), std::invalid_argument);
  o = testOptions();
  o.profiles_file = "/nonexistent/profiles.xml";
  EXPECT_THROW(Participant::create(o), std::invalid_argument);
}

TEST(Participant, MalformedXmlProfileNamesTheFile) {
  const std::string path = ::testing::TempDir() + "/broken_profiles.xml";
  std::ofstream(path) << "<dds><profiles><participant profile_name=\"x\"><rtps><builtin>";
  ParticipantOptions o = testOptions();
  o.profiles_file = path;
  try {
    Participant::create(o);
    FAIL();
  } catch (const mcvio::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(PubSub, TypedImageAndImuArriveIntact) {
  auto participant = Participant::create(testOptions());
  auto node = participant->createNode("test_talker");
  std::atomic<int> images{0}, imus{0};
  Image last_image;
  std::mutex m;
  auto img_sub = node->createSubscription<Image>("/cam0/image_raw", QosProfile::defaults(), [&](const Image& i) {
    std::lock_guard<std::mutex> lock(m);
    last_image = i;
    ++images;
  });
  auto imu_sub = node->createSubscription<Imu>("/imu0", QosProfile::defaults(), [&](const Imu& i) {
    if (i.linear_acceleration().z() == 9.81) ++imus;
  });
  auto img_pub = node->createPublisher<Image>("/cam0/image_raw", QosProfile::defaults());
  auto imu_pub = node->createPublisher<Imu>("/imu0", QosProfile::defaults());
  ASSERT_TRUE(img_pub->waitForReaders(1, 5s));
  ASSERT_TRUE(imu_pub->waitForReaders(1, 5s));
  const Image sent = makeImage(7);
  ASSERT_TRUE(img_pub->publish(sent));
  Imu imu;
  imu.linear_acceleration().z(9.81);
  ASSERT_TRUE(imu_pub->publish(imu));
  ASSERT_TRUE(eventually([&] { return images.load() == 1 && imus.load() == 1; }));
  std::lock_guard<std::mutex> lock(m);
  EXPECT_EQ(last_image, sent);
}

TEST(PubSub, GenericSubscriptionGetsTheExactCdrBytesAndGraphShowsRosNames) {
  auto talker_participant = Participant::create(testOptions());
  auto talker = talker_participant->createNode("talker", "/mcvio");
  auto pub = talker->createPublisher<Image>("/cam1/image_raw", QosProfile::defaults());

  GraphMonitor monitor;
  auto listener_participant = Participant::create(testOptions(), &monitor);
  auto listener = listener_participant->createNode("listener");
  monitor.watchNodes(*listener);
  ASSERT_TRUE(monitor.waitFor([](const auto& topics) {
    for (const auto& t : topics) if (t.name == "/cam1/image_raw" && t.publishers > 0) return true;
    return false;
  }, 10s));
  DiscoveredTopic found;
  for (const auto& t : monitor.topics()) if (t.name == "/cam1/image_raw") found = t;
  EXPECT_EQ(found.type, "sensor_msgs/msg/Image");
  EXPECT_EQ(found.dds_type, "sensor_msgs::msg::dds_::Image_");
  EXPECT_TRUE(found.is_ros);
  EXPECT_EQ(found.type_hash.substr(0, 7), "RIHS01_");
  ASSERT_TRUE(eventually([&] {
    for (const auto& n : monitor.nodes()) if (n.fullName() == "/mcvio/talker") return true;
    return false;
  }));

  std::mutex m;
  std::vector<RawPayload> received;
  GenericSubscription sub(*listener, "/cam1/image_raw", found.dds_type, found.type_hash, QosProfile::defaults(),
                          [&](const ReceivedPayload& p) {
                            std::lock_guard<std::mutex> lock(m);
                            received.push_back(*p.payload);
                          });
  ASSERT_TRUE(pub->waitForReaders(1, 5s));
  Image sent = makeImage(3);
  ASSERT_TRUE(pub->publish(sent));
  ASSERT_TRUE(eventually([&] { std::lock_guard<std::mutex> l(m); return received.size() == 1; }));
  sensor_msgs::msg::dds_::Image_PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t expected(type.getSerializedSizeProvider(&sent)());
  ASSERT_TRUE(type.serialize(&sent, &expected));
  std::lock_guard<std::mutex> lock(m);
  ASSERT_EQ(received[0].size(), expected.length);
  EXPECT_TRUE(std::equal(received[0].begin(), received[0].end(), expected.data));
}

TEST(PubSub, RemappedNodeUsesTheTargetTopicsOnTheBus) {
  auto participant = Participant::create(testOptions());
  // A driver's name on one side, mcvio's on the other: the remapped node talks to the driver.
  auto driver = participant->createNode("camera_driver");
  auto remapped = participant->createNode(
      "frontend", "/mcvio", mcvio::TopicRemapping::parse({"/imu0:=/camera/imu", "/cam9/typo:=/nowhere"}));
  std::atomic<int> received{0};
  auto sub = remapped->createSubscription<Imu>("/imu0", QosProfile::defaults(), [&](const Imu&) { ++received; });
  EXPECT_EQ(sub->topic(), "/camera/imu");
  auto pub = driver->createPublisher<Imu>("/camera/imu", QosProfile::defaults());
  auto unmapped_pub = driver->createPublisher<Imu>("/imu0", QosProfile::defaults());
  ASSERT_TRUE(pub->waitForReaders(1, 5s));
  EXPECT_EQ(unmapped_pub->matchedReaders(), 0);
  ASSERT_TRUE(pub->publish(Imu()));
  ASSERT_TRUE(eventually([&] { return received.load() == 1; }));
  EXPECT_EQ(remapped->unusedRemapRules(), std::vector<std::string>{"/cam9/typo:=/nowhere"});
  EXPECT_TRUE(driver->unusedRemapRules().empty());
  // Publishers are remapped too, and relative names are absolute.
  auto out = remapped->createPublisher<Imu>("cam9/typo", QosProfile::defaults());
  EXPECT_EQ(out->topic(), "/nowhere");
  EXPECT_TRUE(remapped->unusedRemapRules().empty());
  // A default learnt later (a calibration's topic) gives way to a rule the node was given.
  EXPECT_FALSE(remapped->remapByDefault("/imu0", "/calibrated/imu"));
  EXPECT_EQ(remapped->resolveTopic("/imu0"), "/camera/imu");
  EXPECT_TRUE(remapped->remapByDefault("cam0/image_raw", "/calibrated/left"));
  EXPECT_EQ(remapped->resolveTopic("/cam0/image_raw"), "/calibrated/left");
  EXPECT_THROW(remapped->remapByDefault("/cam1/image_raw", "not a name"), mcvio::InputError);
}

TEST(PubSub, LosslessProfileDeliversEverySampleToASlowReader) {
  auto participant = Participant::create(testOptions());
  auto node = participant->createNode("lossless");
  constexpr int kCount = 400;
  std::atomic<int> received{0};
  std::atomic<bool> in_order{true};
  auto sub = node->createSubscription<Imu>("/imu_lossless", QosProfile::lossless(), [&](const Imu& imu) {
    if (static_cast<int>(imu.header().stamp().nanosec()) != received.load()) in_order = false;
    ++received;
    if (received % 50 == 0) std::this_thread::sleep_for(20ms);  // a reader that falls behind
  });
  auto pub = node->createPublisher<Imu>("/imu_lossless", QosProfile::lossless());
  ASSERT_TRUE(pub->waitForReaders(1, 5s));
  for (int i = 0; i < kCount; ++i) {
    Imu imu;
    imu.header().stamp().nanosec(static_cast<std::uint32_t>(i));
    ASSERT_TRUE(pub->publish(imu));
  }
  ASSERT_TRUE(eventually([&] { return received.load() == kCount; }, 30s)) << received.load();
  EXPECT_TRUE(in_order.load());
}
