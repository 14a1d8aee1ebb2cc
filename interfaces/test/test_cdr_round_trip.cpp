#include <gtest/gtest.h>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "mcvio/interfaces/ros_type_traits.hpp"

using namespace mcvio::interfaces;

namespace {

// Serialises with the generated TopicDataType, as a DataWriter does, and reads it back.
template <class T>
T roundTrip(T& msg, std::vector<std::uint8_t>* bytes = nullptr) {
  typename RosType<T>::PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&msg)());
  EXPECT_TRUE(type.serialize(&msg, &payload));
  if (bytes) bytes->assign(payload.data, payload.data + payload.length);
  T out;
  EXPECT_TRUE(type.deserialize(&payload, &out));
  return out;
}

std_msgs::msg::dds_::Header_ header(const char* frame) {
  std_msgs::msg::dds_::Header_ h;
  h.stamp().sec(1403715273);
  h.stamp().nanosec(262142976);
  h.frame_id(frame);
  return h;
}

}  // namespace

TEST(CdrRoundTrip, TimeHasThePlainCdrLittleEndianLayout) {
  builtin_interfaces::msg::dds_::Time_ t;
  t.sec(-2);
  t.nanosec(300000000);
  std::vector<std::uint8_t> bytes;
  EXPECT_EQ(roundTrip(t, &bytes), t);
  const std::vector<std::uint8_t> expected = {0x00, 0x01, 0x00, 0x00, 0xfe, 0xff, 0xff, 0xff,
                                              0x00, 0xa3, 0xe1, 0x11};
  EXPECT_EQ(bytes, expected);
}

TEST(CdrRoundTrip, Image) {
  sensor_msgs::msg::dds_::Image_ m;
  m.header(header("cam0"));
  m.height(480);
  m.width(752);
  m.encoding("mono8");
  m.step(752);
  m.data().resize(752 * 480);
  for (std::size_t i = 0; i < m.data().size(); ++i) m.data()[i] = static_cast<std::uint8_t>(i * 7);
  EXPECT_EQ(roundTrip(m), m);
}

TEST(CdrRoundTrip, ImuAndCameraInfo) {
  sensor_msgs::msg::dds_::Imu_ imu;
  imu.header(header("imu0"));
  imu.orientation().w(0.5);
  imu.angular_velocity().z(-0.25);
  imu.linear_acceleration().x(9.81);
  for (int i = 0; i < 9; ++i) imu.angular_velocity_covariance()[i] = i * 1e-4;
  EXPECT_EQ(roundTrip(imu), imu);

  sensor_msgs::msg::dds_::CameraInfo_ ci;
  ci.header(header("cam1"));
  ci.height(480);
  ci.width(752);
  ci.distortion_model("plumb_bob");
  ci.d({-0.28, 0.07, 0.0002, 1.7e-05, 0.0});
  ci.k()[0] = 458.654;
  ci.p()[11] = 1.0;
  ci.roi().do_rectify(true);
  EXPECT_EQ(roundTrip(ci), ci);
}

TEST(CdrRoundTrip, OdometryPathTfAndPointCloud) {
  nav_msgs::msg::dds_::Odometry_ o;
  o.header(header("world"));
  o.child_frame_id("imu0");
  o.pose().pose().position().x(1.5);
  o.pose().covariance()[35] = 0.01;
  o.twist().twist().angular().y(-0.1);
  EXPECT_EQ(roundTrip(o), o);

  nav_msgs::msg::dds_::Path_ p;
  p.header(header("world"));
  p.poses().resize(3);
  p.poses()[2].pose().orientation().w(1.0);
  EXPECT_EQ(roundTrip(p), p);

  tf2_msgs::msg::dds_::TFMessage_ tf;
  tf.transforms().resize(2);
  tf.transforms()[1].child_frame_id("cam0");
  tf.transforms()[1].transform().translation().x(0.05);
  EXPECT_EQ(roundTrip(tf), tf);

  sensor_msgs::msg::dds_::PointCloud2_ pc;
  pc.header(header("world"));
  pc.fields().resize(3);
  pc.fields()[0].name("x");
  pc.fields()[0].datatype(sensor_msgs::msg::PointField_Constants::FLOAT32);
  pc.data(std::vector<std::uint8_t>(36, 3));
  pc.is_dense(true);
  EXPECT_EQ(roundTrip(pc), pc);
}

TEST(CdrRoundTrip, DiscoveryInfoAndMcvioTypes) {
  rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_ info;
  info.gid().data()[15] = 0xc1;
  info.node_entities_info_seq().resize(1);
  info.node_entities_info_seq()[0].node_name("backend");
  info.node_entities_info_seq()[0].node_namespace("/mcvio");
  info.node_entities_info_seq()[0].writer_gid_seq().resize(2);
  EXPECT_EQ(roundTrip(info), info);

  mcvio_msgs::msg::dds_::FeatureFrame_ ff;
  ff.header(header("cam0"));
  ff.frame_index(12);
  ff.features().resize(2);
  ff.features()[1].track_id(1234567890123ull);
  ff.features()[1].camera_index(1);
  ff.features()[1].u(100.25);
  ff.features()[1].label(mcvio_msgs::msg::Feature_Constants::LABEL_INCONSISTENT);
  EXPECT_EQ(roundTrip(ff), ff);

  mcvio_msgs::msg::dds_::MotionConflict_ mc;
  mc.header(header("imu0"));
  mc.state(mcvio_msgs::msg::MotionConflict_Constants::STATE_CONFLICT);
  mc.propagated_chi2(42.0);
  mc.resolution_mode("auto");
  EXPECT_EQ(roundTrip(mc), mc);
}
