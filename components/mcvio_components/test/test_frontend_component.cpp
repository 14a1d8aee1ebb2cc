// The frontend component on the bus: the real excerpt played losslessly yields one FeatureFrame per
// stereo pair, each with at least 120 stereo-matched features; bad images are skipped, not fatal.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <thread>
#include <unistd.h>

#include "mcvio/components/frontend_component.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "component_test_support.hpp"

using namespace mcvio;
using namespace std::chrono_literals;

namespace {

using components::test::excerptDir;
using components::test::testParticipantOptions;

}  // namespace

TEST(FrontendComponent, RealExcerptGivesAFeatureFramePerPairWithEnoughStereoMatches) {
  const auto dir = excerptDir();
  if (dir.empty()) GTEST_SKIP() << "no ../shared/data/euroc_V1_01_excerpt";
  const auto data = dataset::EurocDataset::open(dir);
  auto participant = mcvio::dds::Participant::create(testParticipantOptions(31));
  std::mutex m;
  std::vector<FeatureFrame> frames;
  auto listener = participant->createNode("listener");
  auto sub = listener->createSubscription<mcvio_msgs::msg::dds_::FeatureFrame_>(
      "/mcvio/features", mcvio::dds::QosProfile::lossless(), [&](const mcvio_msgs::msg::dds_::FeatureFrame_& f) {
        std::lock_guard<std::mutex> lock(m);
        frames.push_back(components::fromFeatureFrameMsg(f));
      });
  components::FrontendComponentOptions fo;
  fo.calibration_dir = dir;
  fo.lossless = true;
  components::FrontendComponent frontend(participant->createNode("frontend"), fo);

  auto player_participant = mcvio::dds::Participant::create(testParticipantOptions(31));
  components::PlayerOptions po;
  po.lossless = true;
  po.progress = false;
  po.min_readers = 1;
  po.wait_for_readers_s = 20;
  components::Player player(player_participant->createNode("player"), data, po);
  // The player waits for readers of every topic; the frontend reads images and IMU, not the rest.
  std::thread feeder([&] {
    auto extra = player_participant->createNode("extra_readers");
    auto a = extra->createSubscription<sensor_msgs::msg::dds_::CameraInfo_>("/cam0/camera_info", mcvio::dds::QosProfile::lossless(), [](const auto&) {});
    auto b = extra->createSubscription<sensor_msgs::msg::dds_::CameraInfo_>("/cam1/camera_info", mcvio::dds::QosProfile::lossless(), [](const auto&) {});
    auto c = extra->createSubscription<nav_msgs::msg::dds_::Odometry_>("/ground_truth/odometry", mcvio::dds::QosProfile::lossless(), [](const auto&) {});
    player.run();
  });
  feeder.join();
  const auto deadline = std::chrono::steady_clock::now() + 120s;
  while (std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (frames.size() == data.stereoFrames().size()) break;
    }
    std::this_thread::sleep_for(50ms);
  }
  std::lock_guard<std::mutex> lock(m);
  ASSERT_EQ(frames.size(), data.stereoFrames().size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].t, data.stereoFrames()[i].t);
    const auto stereo = std::count_if(frames[i].features.begin(), frames[i].features.end(),
                                      [](const FeatureObservation& o) { return o.camera_index == 1; });
    EXPECT_GE(stereo, 120) << "frame " << i;
  }
  EXPECT_EQ(frontend.stats().frames_skipped, 0u);
}

TEST(FrontendComponent, WrongEncodingAndMissingCalibrationAreSkippedNotFatal) {
  auto participant = mcvio::dds::Participant::create(testParticipantOptions(61));
  components::FrontendComponentOptions fo;
  fo.lossless = true;  // no calibration_dir: frames are skipped with a message
  components::FrontendComponent frontend(participant->createNode("frontend"), fo);
  auto pub_node = participant->createNode("camera");
  auto left = pub_node->createPublisher<sensor_msgs::msg::dds_::Image_>("/cam0/image_raw", mcvio::dds::QosProfile::lossless());
  auto right = pub_node->createPublisher<sensor_msgs::msg::dds_::Image_>("/cam1/image_raw", mcvio::dds::QosProfile::lossless());
  ASSERT_TRUE(left->waitForReaders(1, 10s));
  ASSERT_TRUE(right->waitForReaders(1, 10s));
  cv::Mat img(48, 64, CV_8UC1, cv::Scalar(100));
  auto bad = components::toImageMsg(img, 1000, "cam0");
  bad.encoding("bgr8");
  left->publish(bad);
  left->publish(components::toImageMsg(img, 2000, "cam0"));
  right->publish(components::toImageMsg(img, 2000, "cam1"));
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (std::chrono::steady_clock::now() < deadline &&
         (frontend.stats().bad_images < 1 || frontend.stats().frames_skipped < 1)) {
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(frontend.stats().bad_images, 1u);
  EXPECT_EQ(frontend.stats().frames_skipped, 1u);  // no calibration yet
  EXPECT_EQ(frontend.stats().frames_published, 0u);
}
