#include "mcvio/components/ros_conversions.hpp"

#include <stdexcept>

namespace mcvio::components {

std_msgs::msg::dds_::Header_ makeHeader(Timestamp t, const std::string& frame_id) {
  std_msgs::msg::dds_::Header_ h;
  // Floor division keeps nanosec in [0, 1e9) for times before the epoch too.
  std::int64_t sec = t / 1000000000, nsec = t % 1000000000;
  if (nsec < 0) {
    nsec += 1000000000;
    --sec;
  }
  h.stamp().sec(static_cast<std::int32_t>(sec));
  h.stamp().nanosec(static_cast<std::uint32_t>(nsec));
  h.frame_id(frame_id);
  return h;
}

Timestamp stampOf(const std_msgs::msg::dds_::Header_& header) {
  return static_cast<Timestamp>(header.stamp().sec()) * 1000000000 + header.stamp().nanosec();
}

sensor_msgs::msg::dds_::Image_ toImageMsg(const cv::Mat& image, Timestamp t, const std::string& frame_id) {
  if (image.type() != CV_8UC1) throw std::invalid_argument("toImageMsg: only mono8 images (CV_8UC1) are published");
  sensor_msgs::msg::dds_::Image_ msg;
  msg.header(makeHeader(t, frame_id));
  msg.height(static_cast<std::uint32_t>(image.rows));
  msg.width(static_cast<std::uint32_t>(image.cols));
  msg.encoding("mono8");
  msg.step(static_cast<std::uint32_t>(image.cols));
  msg.data().resize(static_cast<std::size_t>(image.rows) * image.cols);
  for (int r = 0; r < image.rows; ++r) {
    std::copy(image.ptr<std::uint8_t>(r), image.ptr<std::uint8_t>(r) + image.cols, msg.data().data() + r * image.cols);
  }
  return msg;
}

sensor_msgs::msg::dds_::Imu_ toImuMsg(const ImuSample& s, const std::string& frame_id) {
  sensor_msgs::msg::dds_::Imu_ msg;
  msg.header(makeHeader(s.t, frame_id));
  msg.orientation().w(1.0);
  msg.orientation_covariance()[0] = -1.0;  // REP-145: no orientation estimate
  msg.angular_velocity().x(s.gyro.x());
  msg.angular_velocity().y(s.gyro.y());
  msg.angular_velocity().z(s.gyro.z());
  msg.linear_acceleration().x(s.accel.x());
  msg.linear_acceleration().y(s.accel.y());
  msg.linear_acceleration().z(s.accel.z());
  return msg;
}

sensor_msgs::msg::dds_::CameraInfo_ toCameraInfoMsg(const CameraCalibration& c, Timestamp t) {
  sensor_msgs::msg::dds_::CameraInfo_ msg;
  msg.header(makeHeader(t, c.name));
  msg.height(static_cast<std::uint32_t>(c.model.height()));
  msg.width(static_cast<std::uint32_t>(c.model.width()));
  const auto& k = c.model.distortionCoefficients();
  switch (c.model.distortionModel()) {
    case DistortionModel::kRadialTangential:
      msg.distortion_model("plumb_bob");
      msg.d({k[0], k[1], k[2], k[3], 0.0});
      break;
    case DistortionModel::kEquidistant:
      msg.distortion_model("equidistant");
      msg.d({k[0], k[1], k[2], k[3]});
      break;
    default:
      msg.distortion_model("plumb_bob");
      msg.d({0.0, 0.0, 0.0, 0.0, 0.0});
  }
  msg.k({c.model.fu(), 0, c.model.cu(), 0, c.model.fv(), c.model.cv(), 0, 0, 1});
  msg.r({1, 0, 0, 0, 1, 0, 0, 0, 1});
  msg.p({c.model.fu(), 0, c.model.cu(), 0, 0, c.model.fv(), c.model.cv(), 0, 0, 0, 1, 0});
  return msg;
}

nav_msgs::msg::dds_::Odometry_ toOdometryMsg(const dataset::GroundTruthState& s, const std::string& world_frame,
                                             const std::string& body_frame) {
  nav_msgs::msg::dds_::Odometry_ msg;
  msg.header(makeHeader(s.t, world_frame));
  msg.child_frame_id(body_frame);
  auto& pose = msg.pose().pose();
  pose.position().x(s.p_WB.x());
  pose.position().y(s.p_WB.y());
  pose.position().z(s.p_WB.z());
  pose.orientation().x(s.q_WB.x());
  pose.orientation().y(s.q_WB.y());
  pose.orientation().z(s.q_WB.z());
  pose.orientation().w(s.q_WB.w());
  const Eigen::Vector3d v_B = s.q_WB.conjugate() * s.v_WB;
  msg.twist().twist().linear().x(v_B.x());
  msg.twist().twist().linear().y(v_B.y());
  msg.twist().twist().linear().z(v_B.z());
  return msg;
}

mcvio_msgs::msg::dds_::FeatureFrame_ toFeatureFrameMsg(const FeatureFrame& f) {
  mcvio_msgs::msg::dds_::FeatureFrame_ msg;
  msg.header(makeHeader(f.t, "cam0"));
  msg.frame_index(f.frame_index);
  msg.features().reserve(f.features.size());
  for (const auto& o : f.features) {
    mcvio_msgs::msg::dds_::Feature_ m;
    m.track_id(o.track_id);
    m.camera_index(o.camera_index);
    m.u(o.pixel.x());
    m.v(o.pixel.y());
    m.x(o.normalized.x());
    m.y(o.normalized.y());
    m.label(static_cast<std::uint8_t>(o.label));
    msg.features().push_back(m);
  }
  return msg;
}

FeatureFrame fromFeatureFrameMsg(const mcvio_msgs::msg::dds_::FeatureFrame_& msg) {
  FeatureFrame f;
  f.t = stampOf(msg.header());
  f.frame_index = msg.frame_index();
  f.features.reserve(msg.features().size());
  for (const auto& m : msg.features()) {
    FeatureObservation o;
    o.track_id = m.track_id();
    o.camera_index = m.camera_index();
    o.pixel = {m.u(), m.v()};
    o.normalized = {m.x(), m.y()};
    o.label = m.label() <= 2 ? static_cast<TrackLabel>(m.label()) : TrackLabel::kUnknown;
    f.features.push_back(o);
  }
  return f;
}

}  // namespace mcvio::components
