// The frontend component on the bus: the real excerpt played losslessly yields one FeatureFrame per
// stereo pair, each with at least 120 stereo-matched features; bad images are skipped, not fatal;
// colour images on a driver's topic names (remapped, or named by Kalibr's rostopic) give the
// features of their grey.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <thread>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "mcvio/components/frontend_component.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/dataset/kalibr_calibration.hpp"
#include "component_test_support.hpp"

using namespace mcvio;
using namespace std::chrono_literals;

namespace {

using components::test::excerptDir;
using components::test::testParticipantOptions;
using FeatureMsg = mcvio_msgs::msg::dds_::FeatureFrame_;

// Every FeatureFrame published on `topic`, appended to `frames` under `m`.
std::unique_ptr<mcvio::dds::Subscription<FeatureMsg>> collectFeatures(mcvio::dds::Node& node, const std::string& topic,
                                                                       std::mutex& m, std::vector<FeatureFrame>& frames) {
  return node.createSubscription<FeatureMsg>(topic, mcvio::dds::QosProfile::lossless(), [&m, &frames](const FeatureMsg& f) {
    std::lock_guard<std::mutex> lock(m);
    frames.push_back(components::fromFeatureFrameMsg(f));
  });
}

}  // namespace

TEST(FrontendComponent, RealExcerptGivesAFeatureFramePerPairWithEnoughStereoMatches) {
  const auto dir = excerptDir();
  if (dir.empty()) GTEST_SKIP() << "no ../shared/data/euroc_V1_01_excerpt";
  const auto data = dataset::EurocDataset::open(dir);
  auto participant = mcvio::dds::Participant::create(testParticipantOptions(31));
  std::mutex m;
  std::vector<FeatureFrame> frames;
  auto listener = participant->createNode("listener");
  auto sub = collectFeatures(*listener, "/mcvio/features", m, frames);
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
  bad.encoding("32FC1");  // a depth image on the camera's topic
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

// A colour camera driver on its own topic names: the frontend, remapped onto them, tracks the
// rgb8 / bgr8 images as their grey and publishes the same features as on mono8 images; so does
// one on image_transport's compressed streams (png, lossless).
TEST(FrontendComponent, ColourImagesOnADriversTopicsGiveTheFeaturesOfTheirGrey) {
  const std::string dir = (std::filesystem::temp_directory_path() / ("mcvio_frontend_colour_" + std::to_string(getpid()))).string();
  components::test::writeCleanSequence(dir, 3, 1.0);
  const auto data = dataset::EurocDataset::open(dir);
  auto participant = mcvio::dds::Participant::create(testParticipantOptions(71));
  const auto lossless = mcvio::dds::QosProfile::lossless();
  std::mutex m;
  std::vector<FeatureFrame> grey_frames, colour_frames, png_frames;
  auto listener = participant->createNode("listener");
  auto grey_sub = collectFeatures(*listener, "/mcvio/features", m, grey_frames);
  auto colour_sub = collectFeatures(*listener, "/driver/features", m, colour_frames);
  auto png_sub = collectFeatures(*listener, "/png/features", m, png_frames);
  components::FrontendComponentOptions fo;
  fo.calibration_dir = dir;
  fo.lossless = true;
  components::FrontendComponent grey_frontend(participant->createNode("frontend"), fo);
  auto colour_node = participant->createNode(
      "colour_frontend", "/",
      TopicRemapping::parse({"/cam0/image_raw:=/driver/left/image_color", "/cam1/image_raw:=/driver/right/image_color",
                             "/imu0:=/driver/imu", "/mcvio/features:=/driver/features"}));
  components::FrontendComponent colour_frontend(colour_node, fo);
  EXPECT_TRUE(colour_node->unusedRemapRules().empty());
  auto png_fo = fo;
  png_fo.image_transport = "compressed";
  components::FrontendComponent png_frontend(
      participant->createNode("png_frontend", "/", TopicRemapping::parse({"/mcvio/features:=/png/features"})), png_fo);
  // Kalibr's files naming the driver's topics (rostopic) bring the frontend onto them without
  // --remap, as OpenVINS takes them; a --remap rule for a sensor still wins.
  StereoRigCalibration kalibr_rig = data.calibration();
  kalibr_rig.cam0.topic = "/driver/left/image_color";
  kalibr_rig.cam1.topic = "/driver/right/image_color";
  kalibr_rig.imu.topic = "/driver/imu";
  dataset::KalibrCalibration::write(kalibr_rig, dir + "/kalibr");
  auto kalibr_fo = fo;
  kalibr_fo.calibration_dir = dir + "/kalibr/camchain-imucam.yaml";
  auto kalibr_node = participant->createNode("kalibr_frontend", "/", TopicRemapping::parse({"/mcvio/features:=/kalibr/features"}));
  components::FrontendComponent kalibr_frontend(kalibr_node, kalibr_fo);
  EXPECT_EQ(kalibr_frontend.imageTopics(), (std::vector<std::string>{"/driver/left/image_color", "/driver/right/image_color"}));
  EXPECT_EQ(kalibr_node->resolveTopic("/imu0"), "/driver/imu");
  std::vector<FeatureFrame> kalibr_frames;
  auto kalibr_sub = collectFeatures(*listener, "/kalibr/features", m, kalibr_frames);
  {
    auto keep_node = participant->createNode("kept_frontend", "/", TopicRemapping::parse({"/cam0/image_raw:=/cam0/image_raw"}));
    components::FrontendComponent kept(keep_node, kalibr_fo);
    EXPECT_EQ(kept.imageTopics(), (std::vector<std::string>{"/cam0/image_raw", "/driver/right/image_color"}));
    EXPECT_TRUE(keep_node->unusedRemapRules().empty());
  }

  using ImageMsg = sensor_msgs::msg::dds_::Image_;
  using ImuMsg = sensor_msgs::msg::dds_::Imu_;
  auto camera = participant->createNode("camera");
  auto grey_left = camera->createPublisher<ImageMsg>("/cam0/image_raw", lossless);
  auto grey_right = camera->createPublisher<ImageMsg>("/cam1/image_raw", lossless);
  auto colour_left = camera->createPublisher<ImageMsg>("/driver/left/image_color", lossless);
  auto colour_right = camera->createPublisher<ImageMsg>("/driver/right/image_color", lossless);
  using CompressedMsg = sensor_msgs::msg::dds_::CompressedImage_;
  auto png_left = camera->createPublisher<CompressedMsg>("/cam0/image_raw/compressed", lossless);
  auto png_right = camera->createPublisher<CompressedMsg>("/cam1/image_raw/compressed", lossless);
  auto imu = camera->createPublisher<ImuMsg>("/imu0", lossless);
  auto driver_imu = camera->createPublisher<ImuMsg>("/driver/imu", lossless);
  for (auto* p : std::vector<mcvio::dds::WriterEndpoint*>{grey_left.get(), grey_right.get(), colour_left.get(),
                                                          colour_right.get(), png_left.get(), png_right.get(), imu.get(),
                                                          driver_imu.get()})
    ASSERT_TRUE(p->waitForReaders(1, 10s)) << p->topic();
  for (const auto& s : data.imu()) {
    imu->publish(components::toImuMsg(s, "imu0"));
    driver_imu->publish(components::toImuMsg(s, "imu0"));
  }
  // The grey replicated into three channels, as rgb8 on the left and bgr8 on the right.
  const auto colour = [](const cv::Mat& grey, Timestamp t, const char* encoding) {
    ImageMsg msg = components::toImageMsg(grey, t, "cam");
    msg.encoding(encoding);
    msg.step(static_cast<std::uint32_t>(grey.cols * 3));
    msg.data().resize(grey.total() * 3);
    for (std::size_t i = 0; i < grey.total(); ++i)
      for (int c = 0; c < 3; ++c) msg.data()[i * 3 + c] = grey.data[i];
    return msg;
  };
  const auto png = [](const cv::Mat& grey, Timestamp t) {
    CompressedMsg msg;
    msg.header(components::toImageMsg(grey, t, "cam").header());
    msg.format("mono8; png compressed mono8");
    std::vector<std::uint8_t> bytes;
    cv::imencode(".png", grey, bytes);
    msg.data(bytes);
    return msg;
  };
  for (const auto& f : data.stereoFrames()) {
    cv::Mat left, right;
    std::string error;
    ASSERT_TRUE(data.tryLoadImage(f, 0, &left, &error)) << error;
    ASSERT_TRUE(data.tryLoadImage(f, 1, &right, &error)) << error;
    grey_left->publish(components::toImageMsg(left, f.t, "cam0"));
    grey_right->publish(components::toImageMsg(right, f.t, "cam1"));
    colour_left->publish(colour(left, f.t, "rgb8"));
    colour_right->publish(colour(right, f.t, "bgr8"));
    png_left->publish(png(left, f.t));
    png_right->publish(png(right, f.t));
  }
  const std::size_t n = data.stereoFrames().size();
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (grey_frames.size() == n && colour_frames.size() == n && png_frames.size() == n && kalibr_frames.size() == n) break;
    }
    std::this_thread::sleep_for(20ms);
  }
  std::filesystem::remove_all(dir);
  std::lock_guard<std::mutex> lock(m);
  ASSERT_EQ(grey_frames.size(), n);
  ASSERT_EQ(colour_frames.size(), n);
  ASSERT_EQ(png_frames.size(), n);
  ASSERT_EQ(kalibr_frames.size(), n);
  EXPECT_EQ(colour_frontend.stats().bad_images, 0u);
  EXPECT_EQ(png_frontend.stats().bad_images, 0u);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(colour_frames[i].features.size(), grey_frames[i].features.size()) << "frame " << i;
    ASSERT_EQ(png_frames[i].features.size(), grey_frames[i].features.size()) << "frame " << i;
    ASSERT_EQ(kalibr_frames[i].features.size(), grey_frames[i].features.size()) << "frame " << i;
    ASSERT_GT(grey_frames[i].features.size(), 50u) << "frame " << i;
    for (std::size_t k = 0; k < grey_frames[i].features.size(); ++k) {
      EXPECT_EQ(colour_frames[i].features[k].track_id, grey_frames[i].features[k].track_id);
      EXPECT_EQ(colour_frames[i].features[k].pixel, grey_frames[i].features[k].pixel);
      EXPECT_EQ(png_frames[i].features[k].pixel, grey_frames[i].features[k].pixel);
      EXPECT_EQ(kalibr_frames[i].features[k].pixel, grey_frames[i].features[k].pixel);
    }
  }
}
