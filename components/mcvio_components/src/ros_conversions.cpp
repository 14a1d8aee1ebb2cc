#include "mcvio/components/ros_conversions.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
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

ImuSample fromImuMsg(const sensor_msgs::msg::dds_::Imu_& m) {
  ImuSample s;
  s.t = stampOf(m.header());
  s.gyro = {m.angular_velocity().x(), m.angular_velocity().y(), m.angular_velocity().z()};
  s.accel = {m.linear_acceleration().x(), m.linear_acceleration().y(), m.linear_acceleration().z()};
  return s;
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
    // sensor_msgs has no names for the two wide-angle models; these say which, with their two
    // parameters in Kalibr's order (image_proc and RViz cannot rectify them).
    case DistortionModel::kDoubleSphere:
      msg.distortion_model("double_sphere");
      msg.d({k[0], k[1]});
      break;
    case DistortionModel::kExtendedUnified:
      msg.distortion_model("extended_unified");
      msg.d({k[0], k[1]});
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

namespace {

void setPose(geometry_msgs::msg::dds_::Pose_& pose, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  pose.position().x(p.x());
  pose.position().y(p.y());
  pose.position().z(p.z());
  pose.orientation().x(q.x());
  pose.orientation().y(q.y());
  pose.orientation().z(q.z());
  pose.orientation().w(q.w());
}

void setVector(geometry_msgs::msg::dds_::Vector3_& v, const Eigen::Vector3d& x) {
  v.x(x.x());
  v.y(x.y());
  v.z(x.z());
}

}  // namespace

nav_msgs::msg::dds_::Odometry_ toOdometryMsg(const estimator::EstimatorOutput& e, const Eigen::Vector3d& omega_B,
                                             const std::string& world_frame, const std::string& body_frame) {
  nav_msgs::msg::dds_::Odometry_ msg;
  msg.header(makeHeader(e.t, world_frame));
  msg.child_frame_id(body_frame);
  const Eigen::Quaterniond q = e.q_WB.normalized();
  setPose(msg.pose().pose(), e.p_WB, q);
  auto& cov = msg.pose().covariance();
  if (e.covariance_valid) {
    // dtheta_W = R dtheta_B: J = diag(I, R), Sigma_ros = J Sigma J^T.
    Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Identity();
    J.bottomRightCorner<3, 3>() = q.toRotationMatrix();
    const Eigen::Matrix<double, 6, 6> world = J * e.pose_covariance * J.transpose();
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) cov[static_cast<std::size_t>(r * 6 + c)] = 0.5 * (world(r, c) + world(c, r));
  } else {
    cov[0] = -1.0;
  }
  setVector(msg.twist().twist().linear(), q.conjugate() * e.v_WB);
  setVector(msg.twist().twist().angular(), omega_B);
  msg.twist().covariance()[0] = -1.0;  // no velocity covariance is estimated
  return msg;
}

nav_msgs::msg::dds_::Odometry_ toSecondaryOdometryMsg(const estimator::EstimatorOutput& e, const std::string& world_frame,
                                                      const std::string& secondary_frame) {
  nav_msgs::msg::dds_::Odometry_ msg;
  msg.header(makeHeader(e.t, world_frame));
  msg.child_frame_id(secondary_frame);
  const Eigen::Quaterniond q = e.conflict.q_WS.normalized();
  setPose(msg.pose().pose(), e.conflict.p_WS, q);
  setVector(msg.twist().twist().linear(), q.conjugate() * e.conflict.v_WS);
  msg.pose().covariance()[0] = -1.0;
  msg.twist().covariance()[0] = -1.0;
  return msg;
}

nav_msgs::msg::dds_::Path_ toPathMsg(const std::vector<StampedPose>& poses, const std::string& frame_id) {
  nav_msgs::msg::dds_::Path_ msg;
  msg.header(makeHeader(poses.empty() ? 0 : poses.back().t, frame_id));
  msg.poses().reserve(poses.size());
  for (const auto& p : poses) {
    geometry_msgs::msg::dds_::PoseStamped_ ps;
    ps.header(makeHeader(p.t, frame_id));
    setPose(ps.pose(), p.p, p.q.normalized());
    msg.poses().push_back(std::move(ps));
  }
  return msg;
}

geometry_msgs::msg::dds_::TransformStamped_ toTransformStamped(const Eigen::Isometry3d& T, Timestamp t,
                                                               const std::string& parent, const std::string& child) {
  geometry_msgs::msg::dds_::TransformStamped_ msg;
  msg.header(makeHeader(t, parent));
  msg.child_frame_id(child);
  setVector(msg.transform().translation(), T.translation());
  const Eigen::Quaterniond q(T.linear());
  msg.transform().rotation().x(q.x());
  msg.transform().rotation().y(q.y());
  msg.transform().rotation().z(q.z());
  msg.transform().rotation().w(q.w());
  return msg;
}

tf2_msgs::msg::dds_::TFMessage_ toTfMessage(const std::vector<geometry_msgs::msg::dds_::TransformStamped_>& transforms) {
  tf2_msgs::msg::dds_::TFMessage_ msg;
  msg.transforms(transforms);
  return msg;
}

sensor_msgs::msg::dds_::PointCloud2_ toPointCloud2Msg(const std::vector<Eigen::Vector3d>& points, Timestamp t,
                                                      const std::string& frame_id) {
  sensor_msgs::msg::dds_::PointCloud2_ msg;
  msg.header(makeHeader(t, frame_id));
  const char* names[3] = {"x", "y", "z"};
  for (std::uint32_t i = 0; i < 3; ++i) {
    sensor_msgs::msg::dds_::PointField_ f;
    f.name(names[i]);
    f.offset(4 * i);
    f.datatype(7);  // FLOAT32
    f.count(1);
    msg.fields().push_back(f);
  }
  constexpr std::uint32_t kPointStep = 12;
  std::vector<std::uint8_t> data;
  data.reserve(points.size() * kPointStep);
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    for (int k = 0; k < 3; ++k) {
      const float v = static_cast<float>(p[k]);
      std::uint32_t bits;
      std::memcpy(&bits, &v, 4);
      // Little endian on the wire whatever the host.
      for (int b = 0; b < 4; ++b) data.push_back(static_cast<std::uint8_t>(bits >> (8 * b)));
    }
  }
  const auto n = static_cast<std::uint32_t>(data.size() / kPointStep);
  msg.height(1);
  msg.width(n);
  msg.is_bigendian(false);
  msg.point_step(kPointStep);
  msg.row_step(kPointStep * n);
  msg.is_dense(true);
  msg.data(std::move(data));
  return msg;
}

mcvio_msgs::msg::dds_::MotionConflict_ toMotionConflictMsg(const estimator::EstimatorOutput& e,
                                                           const std::string& world_frame) {
  mcvio_msgs::msg::dds_::MotionConflict_ msg;
  const auto& c = e.conflict;
  msg.header(makeHeader(e.t, world_frame));
  msg.state(static_cast<std::uint8_t>(c.state));
  msg.propagated_chi2(c.propagated_chi2);
  msg.propagated_threshold(c.propagated_threshold);
  msg.landmarks_tested(static_cast<std::uint32_t>(std::max(0, c.landmarks_tested)));
  msg.landmarks_inconsistent(static_cast<std::uint32_t>(std::max(0, c.landmarks_inconsistent)));
  msg.inconsistent_fraction(c.inconsistent_fraction);
  msg.coherence(c.coherence);
  msg.interval_start(makeHeader(c.interval_start, "").stamp());
  msg.interval_onset(makeHeader(c.interval_onset, "").stamp());
  msg.interval_end(makeHeader(c.interval_end, "").stamp());
  msg.resolution_mode(c.resolution_mode);
  msg.frontend_checked(static_cast<std::uint32_t>(std::max(0, c.frontend_checked)));
  msg.frontend_inconsistent(static_cast<std::uint32_t>(std::max(0, c.frontend_inconsistent)));
  msg.accel_bias_drift(c.accel_bias_drift);
  msg.split_chi2(c.split_chi2);
  msg.evidence_score(c.evidence_score);
  return msg;
}

}  // namespace mcvio::components
