#include "interop_messages.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <utility>

namespace mcvio::interop {
namespace {

using Members = std::initializer_list<std::pair<const char*, std::string>>;

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

std::string number(std::int64_t v) { return std::to_string(v); }

std::string boolean(bool v) { return v ? "true" : "false"; }

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string object(Members members) {
  std::string out = "{";
  bool first = true;
  for (const auto& [name, value] : members) {
    out += first ? "" : ", ";
    out += quoted(name) + ": " + value;
    first = false;
  }
  return out + "}";
}

template <class Container, class ToJson>
std::string array(const Container& items, ToJson to_json) {
  std::string out = "[";
  bool first = true;
  for (const auto& item : items) {
    out += first ? "" : ",";
    out += to_json(item);
    first = false;
  }
  return out + "]";
}

template <class Container>
std::string doubles(const Container& values) {
  return array(values, [](double v) { return number(v); });
}

std::string json(const builtin_interfaces::msg::dds_::Time_& t) {
  return object({{"sec", number(std::int64_t{t.sec()})}, {"nanosec", number(std::int64_t{t.nanosec()})}});
}

std::string json(const std_msgs::msg::dds_::Header_& h) {
  return object({{"stamp", json(h.stamp())}, {"frame_id", quoted(h.frame_id())}});
}

std::string json(const geometry_msgs::msg::dds_::Vector3_& v) {
  return object({{"x", number(v.x())}, {"y", number(v.y())}, {"z", number(v.z())}});
}

std::string json(const geometry_msgs::msg::dds_::Point_& p) {
  return object({{"x", number(p.x())}, {"y", number(p.y())}, {"z", number(p.z())}});
}

std::string json(const geometry_msgs::msg::dds_::Quaternion_& q) {
  return object(
      {{"x", number(q.x())}, {"y", number(q.y())}, {"z", number(q.z())}, {"w", number(q.w())}});
}

std::string json(const geometry_msgs::msg::dds_::Pose_& p) {
  return object({{"position", json(p.position())}, {"orientation", json(p.orientation())}});
}

std::string json(const geometry_msgs::msg::dds_::Twist_& t) {
  return object({{"linear", json(t.linear())}, {"angular", json(t.angular())}});
}

std::string json(const geometry_msgs::msg::dds_::TransformStamped_& t) {
  return object({{"header", json(t.header())},
                 {"child_frame_id", quoted(t.child_frame_id())},
                 {"transform", object({{"translation", json(t.transform().translation())},
                                       {"rotation", json(t.transform().rotation())}})}});
}

std::string json(const sensor_msgs::msg::dds_::Image_& m) {
  return object({{"header", json(m.header())},
                 {"height", number(std::int64_t{m.height()})},
                 {"width", number(std::int64_t{m.width()})},
                 {"encoding", quoted(m.encoding())},
                 {"is_bigendian", number(std::int64_t{m.is_bigendian()})},
                 {"step", number(std::int64_t{m.step()})},
                 {"data", array(m.data(), [](std::uint8_t v) { return std::to_string(v); })}});
}

std::string json(const sensor_msgs::msg::dds_::Imu_& m) {
  return object({{"header", json(m.header())},
                 {"orientation", json(m.orientation())},
                 {"orientation_covariance", doubles(m.orientation_covariance())},
                 {"angular_velocity", json(m.angular_velocity())},
                 {"angular_velocity_covariance", doubles(m.angular_velocity_covariance())},
                 {"linear_acceleration", json(m.linear_acceleration())},
                 {"linear_acceleration_covariance", doubles(m.linear_acceleration_covariance())}});
}

std::string json(const sensor_msgs::msg::dds_::CameraInfo_& m) {
  const auto& roi = m.roi();
  return object({{"header", json(m.header())},
                 {"height", number(std::int64_t{m.height()})},
                 {"width", number(std::int64_t{m.width()})},
                 {"distortion_model", quoted(m.distortion_model())},
                 {"d", doubles(m.d())},
                 {"k", doubles(m.k())},
                 {"r", doubles(m.r())},
                 {"p", doubles(m.p())},
                 {"binning_x", number(std::int64_t{m.binning_x()})},
                 {"binning_y", number(std::int64_t{m.binning_y()})},
                 {"roi", object({{"x_offset", number(std::int64_t{roi.x_offset()})},
                                 {"y_offset", number(std::int64_t{roi.y_offset()})},
                                 {"height", number(std::int64_t{roi.height()})},
                                 {"width", number(std::int64_t{roi.width()})},
                                 {"do_rectify", boolean(roi.do_rectify())}})}});
}

std::string json(const nav_msgs::msg::dds_::Odometry_& m) {
  return object({{"header", json(m.header())},
                 {"child_frame_id", quoted(m.child_frame_id())},
                 {"pose", object({{"pose", json(m.pose().pose())},
                                  {"covariance", doubles(m.pose().covariance())}})},
                 {"twist", object({{"twist", json(m.twist().twist())},
                                   {"covariance", doubles(m.twist().covariance())}})}});
}

std::string json(const tf2_msgs::msg::dds_::TFMessage_& m) {
  return object({{"transforms", array(m.transforms(), [](const auto& t) { return json(t); })}});
}

std_msgs::msg::dds_::Header_ header(std::int32_t sec, std::uint32_t nanosec, const char* frame) {
  std_msgs::msg::dds_::Header_ h;
  h.stamp().sec(sec);
  h.stamp().nanosec(nanosec);
  h.frame_id(frame);
  return h;
}

geometry_msgs::msg::dds_::Vector3_ vector3(double x, double y, double z) {
  geometry_msgs::msg::dds_::Vector3_ v;
  v.x(x);
  v.y(y);
  v.z(z);
  return v;
}

// A unit quaternion from a rotation of `angle` about the (unnormalised) axis (ax, ay, az).
geometry_msgs::msg::dds_::Quaternion_ quaternion(double angle, double ax, double ay, double az) {
  const double n = std::sqrt(ax * ax + ay * ay + az * az);
  const double s = std::sin(angle / 2) / n;
  geometry_msgs::msg::dds_::Quaternion_ q;
  q.x(ax * s);
  q.y(ay * s);
  q.z(az * s);
  q.w(std::cos(angle / 2));
  return q;
}

// Symmetric, positive definite-looking covariance whose every entry differs.
template <std::size_t N, std::size_t Dim>
std::array<double, N> covariance(double scale) {
  std::array<double, N> c{};
  for (std::size_t i = 0; i < Dim; ++i) {
    for (std::size_t j = 0; j < Dim; ++j) {
      c[i * Dim + j] = i == j ? scale * (1.0 + i / 7.0) : scale * (0.01 + (i + j) / 300.0) / 3.0;
    }
  }
  return c;
}

}  // namespace

InteropMessages InteropMessages::make() {
  // EuRoC-like stamps: V1_01 starts at 1403715273.262142976.
  constexpr std::int32_t kSec = 1403715273;
  constexpr std::uint32_t kNanosec = 262142976;
  InteropMessages m;

  auto& image = m.image;
  image.header(header(kSec, kNanosec, "cam0"));
  image.height(480);
  image.width(752);
  image.encoding("mono8");
  image.is_bigendian(1);
  image.step(752);
  image.data().resize(std::size_t{752} * 480);
  for (std::size_t y = 0; y < 480; ++y) {
    for (std::size_t x = 0; x < 752; ++x) {
      image.data()[y * 752 + x] = static_cast<std::uint8_t>((x * 3 + y * 5 + (x * y) % 7) & 0xff);
    }
  }

  auto& imu = m.imu;
  imu.header(header(kSec, kNanosec + 1000000, "imu0"));
  imu.orientation(quaternion(0.3, 0.1, -0.2, 0.97));
  imu.orientation_covariance(covariance<9, 3>(1e-3 / 3));
  imu.angular_velocity(vector3(-0.0027925268031909274, 0.013962634015954637, 0.1 / 3));
  imu.angular_velocity_covariance(covariance<9, 3>(1.7e-4 / 7));
  imu.linear_acceleration(vector3(9.1346938775510203, 0.24525, -3.3333333333333335));
  imu.linear_acceleration_covariance(covariance<9, 3>(2.0e-3 / 9));

  // EuRoC cam0 intrinsics and distortion, with a small rectifying rotation.
  auto& info = m.camera_info;
  info.header(header(kSec, kNanosec, "cam0"));
  info.height(480);
  info.width(752);
  info.distortion_model("plumb_bob");
  info.d({-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 1.0 / 3e5});
  info.k({458.654, 0.1 / 3, 367.215, 0.0, 457.296, 248.375, 0.0, 0.0, 1.0});
  const auto rot = quaternion(0.01, 0.3, 0.5, 0.8);
  const double qx = rot.x(), qy = rot.y(), qz = rot.z(), qw = rot.w();
  info.r({1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw),
          2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw),
          2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)});
  info.p({435.2046959714599, 0.0, 367.4517211914062, -47.90639384423901, 0.0, 435.2046959714599,
          252.2008514404297, 1.0 / 7, 0.0, 0.0, 1.0, 0.001});
  info.binning_x(2);
  info.binning_y(3);
  info.roi().x_offset(8);
  info.roi().y_offset(6);
  info.roi().height(468);
  info.roi().width(736);
  info.roi().do_rectify(true);

  auto& odom = m.odometry;
  odom.header(header(kSec, kNanosec + 50000000, "odom"));
  odom.child_frame_id("base_link");
  odom.pose().pose().position().x(0.87810349464416504);
  odom.pose().pose().position().y(2.1421420574188232);
  odom.pose().pose().position().z(0.94717073440551758);
  odom.pose().pose().orientation(quaternion(1.1, 0.2, 0.3, 0.9));
  odom.pose().covariance(covariance<36, 6>(1e-2 / 3));
  odom.twist().twist().linear(vector3(0.1 / 3, -0.2 / 3, 0.05 / 7));
  odom.twist().twist().angular(vector3(0.01 / 3, 0.02 / 7, -0.03 / 11));
  odom.twist().covariance(covariance<36, 6>(4e-3 / 7));

  geometry_msgs::msg::dds_::TransformStamped_ world_body;
  world_body.header(header(kSec, kNanosec + 50000000, "world"));
  world_body.child_frame_id("body");
  world_body.transform().translation(vector3(0.87810349464416504, 2.1421420574188232, 0.947));
  world_body.transform().rotation(quaternion(1.1, 0.2, 0.3, 0.9));
  geometry_msgs::msg::dds_::TransformStamped_ body_cam;
  body_cam.header(header(kSec, kNanosec + 50000000, "body"));
  body_cam.child_frame_id("cam0");
  body_cam.transform().translation(vector3(-0.0216401454975, -0.064676986768, 0.00981073058949));
  body_cam.transform().rotation(quaternion(1.5707963267948966 + 0.0148, 0.99, 0.01, 1.0));
  m.tf.transforms({world_body, body_cam});
  return m;
}

std::string InteropMessages::toJson(const std::string& node_namespace, const std::string& node_name,
                                    const std::string& participant_gid) const {
  const auto topic = [](const char* name, const char* type, const std::string& message) {
    return object({{"name", quoted(name)}, {"type", quoted(type)}, {"message", message}});
  };
  std::string topics = "[\n  " + topic("/interop/image", "sensor_msgs/msg/Image", json(image));
  topics += ",\n  " + topic("/interop/imu", "sensor_msgs/msg/Imu", json(imu));
  topics += ",\n  " + topic("/interop/camera_info", "sensor_msgs/msg/CameraInfo", json(camera_info));
  topics += ",\n  " + topic("/interop/odometry", "nav_msgs/msg/Odometry", json(odometry));
  topics += ",\n  " + topic("/tf", "tf2_msgs/msg/TFMessage", json(tf)) + "\n]";
  return object({{"node_namespace", quoted(node_namespace)},
                 {"node_name", quoted(node_name)},
                 {"participant_gid", quoted(participant_gid)},
                 {"topics", topics},
                 {"subscriptions", "[" + object({{"name", quoted(kCommandTopic)},
                                                 {"type", quoted("std_msgs/msg/String")}}) + "]"}}) +
         "\n";
}

}  // namespace mcvio::interop
