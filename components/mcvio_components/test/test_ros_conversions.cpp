#include <gtest/gtest.h>

#include "mcvio/components/ros_conversions.hpp"

using namespace mcvio;
using namespace mcvio::components;

TEST(RosConversions, StampsRoundTripIncludingBeforeTheEpoch) {
  for (Timestamp t : {Timestamp{1403715273262142976}, Timestamp{0}, Timestamp{-1500000000}, Timestamp{999999999}}) {
    const auto h = makeHeader(t, "cam0");
    EXPECT_LT(h.stamp().nanosec(), 1000000000u);
    EXPECT_EQ(stampOf(h), t);
  }
  EXPECT_EQ(makeHeader(-1500000000, "x").stamp().sec(), -2);
  EXPECT_EQ(makeHeader(-1500000000, "x").stamp().nanosec(), 500000000u);
}

TEST(RosConversions, ImageKeepsEveryPixelAndRejectsNonMono8) {
  cv::Mat img(48, 64, CV_8UC1);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) img.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(r * 3 + c);
  const auto roi = img(cv::Rect(4, 2, 32, 20));  // a non-contiguous view
  const auto msg = toImageMsg(roi, 42, "cam1");
  EXPECT_EQ(msg.encoding(), "mono8");
  EXPECT_EQ(msg.width(), 32u);
  EXPECT_EQ(msg.height(), 20u);
  EXPECT_EQ(msg.step(), 32u);
  EXPECT_EQ(msg.header().frame_id(), "cam1");
  EXPECT_EQ(msg.data()[5 * 32 + 7], roi.at<std::uint8_t>(5, 7));
  EXPECT_THROW(toImageMsg(cv::Mat(4, 4, CV_8UC3), 0, "cam0"), std::invalid_argument);
}

TEST(RosConversions, CameraInfoImuAndOdometry) {
  CameraCalibration cal;
  cal.name = "cam1";
  cal.model = CameraModel(752, 480, {458.654, 457.296, 367.215, 248.375}, DistortionModel::kRadialTangential,
                          {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
  const auto ci = toCameraInfoMsg(cal, 7);
  EXPECT_EQ(ci.distortion_model(), "plumb_bob");
  ASSERT_EQ(ci.d().size(), 5u);
  EXPECT_DOUBLE_EQ(ci.d()[0], -0.28340811);
  EXPECT_DOUBLE_EQ(ci.k()[2], 367.215);
  EXPECT_DOUBLE_EQ(ci.p()[5], 457.296);
  EXPECT_EQ(ci.header().frame_id(), "cam1");

  ImuSample s;
  s.t = 5;
  s.gyro = {0.1, -0.2, 0.3};
  s.accel = {0.0, 0.5, 9.81};
  const auto imu = toImuMsg(s, "imu0");
  EXPECT_EQ(imu.angular_velocity().y(), -0.2);
  EXPECT_EQ(imu.linear_acceleration().z(), 9.81);
  EXPECT_EQ(imu.orientation_covariance()[0], -1.0);

  dataset::GroundTruthState g;
  g.t = 9;
  g.p_WB = {1, 2, 3};
  g.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  g.v_WB = {1, 0, 0};  // moving along world x while facing +y: body sees -y
  const auto odom = toOdometryMsg(g, "world", "imu0");
  EXPECT_EQ(odom.child_frame_id(), "imu0");
  EXPECT_EQ(odom.pose().pose().position().z(), 3.0);
  EXPECT_NEAR(odom.twist().twist().linear().y(), -1.0, 1e-12);
}
