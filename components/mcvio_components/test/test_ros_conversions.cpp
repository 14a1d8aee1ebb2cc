#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

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
  // The wide-angle models have no sensor_msgs name: theirs, with the two parameters.
  cal.model = CameraModel(752, 480, {349.7, 348.7, 365.8, 249.3}, DistortionModel::kDoubleSphere, {-0.28, 0.57, 0, 0});
  const auto ds = toCameraInfoMsg(cal, 7);
  EXPECT_EQ(ds.distortion_model(), "double_sphere");
  EXPECT_EQ(ds.d(), (std::vector<double>{-0.28, 0.57}));
  EXPECT_DOUBLE_EQ(ds.k()[0], 349.7);
  cal.model = CameraModel(752, 480, {460.1, 459.3, 365.8, 249.3}, DistortionModel::kExtendedUnified, {0.61, 1.12, 0, 0});
  EXPECT_EQ(toCameraInfoMsg(cal, 7).distortion_model(), "extended_unified");

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

namespace {

estimator::EstimatorOutput trackingEstimate() {
  estimator::EstimatorOutput e;
  e.t = 1403715273262142976;
  e.status = estimator::EstimatorStatus::kTracking;
  e.frame_accepted = true;
  e.p_WB = {1, 2, 3};
  e.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  e.v_WB = {1, 0, 0};
  return e;
}

}  // namespace

TEST(RosConversions, EstimateOdometryTurnsTheRotationCovarianceIntoWorldAxes) {
  auto e = trackingEstimate();
  // Uncertain only about rotation about body x, which faces world +y after the 90 deg yaw, and
  // correlated with world position x.
  e.pose_covariance.setZero();
  e.pose_covariance(0, 0) = 0.04;
  e.pose_covariance(1, 1) = 0.05;
  e.pose_covariance(2, 2) = 0.06;
  e.pose_covariance(3, 3) = 0.01;
  e.pose_covariance(0, 3) = e.pose_covariance(3, 0) = 0.002;
  e.covariance_valid = true;
  const auto msg = toOdometryMsg(e, Eigen::Vector3d(0.1, 0.2, 0.3), "world", "imu0");
  EXPECT_EQ(msg.header().frame_id(), "world");
  EXPECT_EQ(msg.child_frame_id(), "imu0");
  EXPECT_EQ(stampOf(msg.header()), e.t);
  EXPECT_EQ(msg.pose().pose().position().y(), 2.0);
  EXPECT_NEAR(msg.pose().pose().orientation().z(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(msg.pose().pose().orientation().w(), std::sqrt(0.5), 1e-12);
  const auto& c = msg.pose().covariance();
  auto at = [&](int r, int col) { return c[static_cast<std::size_t>(r * 6 + col)]; };
  EXPECT_DOUBLE_EQ(at(0, 0), 0.04);  // position block untouched
  EXPECT_DOUBLE_EQ(at(2, 2), 0.06);
  EXPECT_NEAR(at(3, 3), 0.0, 1e-15);  // rotation about world x: none
  EXPECT_NEAR(at(4, 4), 0.01, 1e-15);  // body x = world y
  EXPECT_NEAR(at(0, 4), 0.002, 1e-15);  // cross term follows the axis
  EXPECT_NEAR(at(4, 0), 0.002, 1e-15);
  EXPECT_NEAR(at(0, 3), 0.0, 1e-15);
  // Twist in the body frame: moving along world x while facing +y is -y in the body.
  EXPECT_NEAR(msg.twist().twist().linear().x(), 0.0, 1e-12);
  EXPECT_NEAR(msg.twist().twist().linear().y(), -1.0, 1e-12);
  EXPECT_EQ(msg.twist().twist().angular().z(), 0.3);
  EXPECT_EQ(msg.twist().covariance()[0], -1.0);  // not estimated

  e.covariance_valid = false;
  EXPECT_EQ(toOdometryMsg(e, Eigen::Vector3d::Zero(), "world", "imu0").pose().covariance()[0], -1.0);
}

TEST(RosConversions, SecondaryOdometryPathAndTransforms) {
  auto e = trackingEstimate();
  e.conflict.secondary_valid = true;
  e.conflict.p_WS = {0, 0, 4};
  e.conflict.q_WS = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  e.conflict.v_WS = {0, 0, 1.5};  // a lift going up
  const auto s = toSecondaryOdometryMsg(e, "world", "conflict_frame");
  EXPECT_EQ(s.child_frame_id(), "conflict_frame");
  EXPECT_EQ(s.pose().pose().position().z(), 4.0);
  EXPECT_NEAR(s.twist().twist().linear().z(), 1.5, 1e-12);
  EXPECT_EQ(s.pose().covariance()[0], -1.0);

  std::vector<StampedPose> poses(3);
  for (int i = 0; i < 3; ++i) {
    poses[i].t = 100 + i;
    poses[i].p = Eigen::Vector3d(i, 0, 0);
  }
  const auto path = toPathMsg(poses, "world");
  ASSERT_EQ(path.poses().size(), 3u);
  EXPECT_EQ(stampOf(path.header()), 102);
  EXPECT_EQ(path.poses()[1].header().frame_id(), "world");
  EXPECT_EQ(stampOf(path.poses()[1].header()), 101);
  EXPECT_EQ(path.poses()[2].pose().position().x(), 2.0);
  EXPECT_EQ(path.poses()[2].pose().orientation().w(), 1.0);
  EXPECT_EQ(toPathMsg({}, "world").poses().size(), 0u);

  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(-0.02, 0.06, 0.01);
  const auto tf = toTfMessage({toTransformStamped(T, 7, "imu0", "cam0"), toTransformStamped(T.inverse(), 7, "cam0", "x")});
  ASSERT_EQ(tf.transforms().size(), 2u);
  const auto& a = tf.transforms()[0];
  EXPECT_EQ(a.header().frame_id(), "imu0");
  EXPECT_EQ(a.child_frame_id(), "cam0");
  EXPECT_EQ(a.transform().translation().y(), 0.06);
  EXPECT_NEAR(a.transform().rotation().x(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(a.transform().rotation().w(), std::sqrt(0.5), 1e-12);
}

TEST(RosConversions, PointCloud2IsPackedLittleEndianFloatXyzWithoutNonFinitePoints) {
  const std::vector<Eigen::Vector3d> points = {{1.5, -2.25, 3.0}, {NAN, 0, 0}, {0.125, 8.0, -1.0}};
  const auto msg = toPointCloud2Msg(points, 55, "world");
  EXPECT_EQ(msg.header().frame_id(), "world");
  EXPECT_EQ(stampOf(msg.header()), 55);
  ASSERT_EQ(msg.fields().size(), 3u);
  const char* names[3] = {"x", "y", "z"};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(msg.fields()[i].name(), names[i]);
    EXPECT_EQ(msg.fields()[i].offset(), 4u * i);
    EXPECT_EQ(msg.fields()[i].datatype(), 7u);  // FLOAT32
    EXPECT_EQ(msg.fields()[i].count(), 1u);
  }
  EXPECT_EQ(msg.height(), 1u);
  EXPECT_EQ(msg.width(), 2u);
  EXPECT_EQ(msg.point_step(), 12u);
  EXPECT_EQ(msg.row_step(), 24u);
  EXPECT_FALSE(msg.is_bigendian());
  EXPECT_TRUE(msg.is_dense());
  ASSERT_EQ(msg.data().size(), 24u);
  auto value = [&](std::size_t point, std::size_t field) {
    std::uint32_t bits = 0;
    for (int b = 0; b < 4; ++b) bits |= static_cast<std::uint32_t>(msg.data()[point * 12 + field * 4 + b]) << (8 * b);
    float v;
    std::memcpy(&v, &bits, 4);
    return v;
  };
  EXPECT_EQ(value(0, 1), -2.25f);
  EXPECT_EQ(value(1, 0), 0.125f);
  EXPECT_EQ(value(1, 2), -1.0f);
  // 1.5f = 0x3FC00000: its low byte comes first.
  EXPECT_EQ(msg.data()[0], 0x00);
  EXPECT_EQ(msg.data()[3], 0x3F);
}

TEST(RosConversions, MotionConflictCarriesEveryField) {
  auto e = trackingEstimate();
  auto& c = e.conflict;
  c.state = estimator::ConflictReport::State::kConflict;
  c.propagated_chi2 = 57.5;
  c.propagated_threshold = 40.0;
  c.landmarks_tested = 80;
  c.landmarks_inconsistent = 30;
  c.inconsistent_fraction = 0.375;
  c.coherence = 0.9;
  c.interval_start = 1403715272500000001;
  c.interval_onset = 1403715271250000000;
  c.interval_end = 1403715275000000002;
  c.resolution_mode = "selective";
  c.frontend_checked = 180;
  c.frontend_inconsistent = 140;
  c.accel_bias_drift = 0.0625;
  c.split_chi2 = 131.25;
  c.evidence_score = 0.375;
  const auto msg = toMotionConflictMsg(e, "world");
  EXPECT_EQ(stampOf(msg.header()), e.t);
  EXPECT_EQ(msg.state(), 2u);
  EXPECT_EQ(msg.propagated_chi2(), 57.5);
  EXPECT_EQ(msg.propagated_threshold(), 40.0);
  EXPECT_EQ(msg.landmarks_tested(), 80u);
  EXPECT_EQ(msg.landmarks_inconsistent(), 30u);
  EXPECT_EQ(msg.inconsistent_fraction(), 0.375);
  EXPECT_EQ(msg.coherence(), 0.9);
  EXPECT_EQ(msg.interval_start().sec(), 1403715272);
  EXPECT_EQ(msg.interval_start().nanosec(), 500000001u);
  EXPECT_EQ(msg.interval_onset().sec(), 1403715271);
  EXPECT_EQ(msg.interval_onset().nanosec(), 250000000u);
  EXPECT_EQ(msg.interval_end().sec(), 1403715275);
  EXPECT_EQ(msg.interval_end().nanosec(), 2u);
  EXPECT_EQ(msg.resolution_mode(), "selective");
  EXPECT_EQ(msg.frontend_checked(), 180u);
  EXPECT_EQ(msg.frontend_inconsistent(), 140u);
  EXPECT_EQ(msg.accel_bias_drift(), 0.0625);
  EXPECT_EQ(msg.split_chi2(), 131.25);
  EXPECT_EQ(msg.evidence_score(), 0.375);
  e.conflict = {};
  const auto none = toMotionConflictMsg(e, "world");
  EXPECT_EQ(none.state(), 0u);
  EXPECT_EQ(none.interval_start().sec(), 0);
  EXPECT_EQ(none.resolution_mode(), "reference");
}
