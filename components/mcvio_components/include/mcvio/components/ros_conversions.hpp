#pragma once
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "mcvio/core/camera_calibration.hpp"
#include "mcvio/core/feature_frame.hpp"
#include "mcvio/core/imu_sample.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"
#include "mcvio/estimator/estimator_output.hpp"
#include "mcvio/interfaces/ros_type_traits.hpp"

namespace mcvio::components {

/// Between mcvio's plain structs and the ROS 2 messages on the bus. Stamps are the data's own
/// int64 nanoseconds, so a bag or a subscriber sees the dataset's time.
std_msgs::msg::dds_::Header_ makeHeader(Timestamp t, const std::string& frame_id);
Timestamp stampOf(const std_msgs::msg::dds_::Header_& header);

/// mono8 image; throws std::invalid_argument for a cv::Mat that is not CV_8UC1.
sensor_msgs::msg::dds_::Image_ toImageMsg(const cv::Mat& image, Timestamp t, const std::string& frame_id);
sensor_msgs::msg::dds_::Imu_ toImuMsg(const ImuSample& sample, const std::string& frame_id);
/// The inverse: stamp, angular velocity and linear acceleration (values as received, unchecked).
ImuSample fromImuMsg(const sensor_msgs::msg::dds_::Imu_& msg);
/// plumb_bob for radial-tangential, "equidistant" for equidistant; R identity, P = [K | 0].
sensor_msgs::msg::dds_::CameraInfo_ toCameraInfoMsg(const CameraCalibration& calibration, Timestamp t);
/// Pose of the body in `world`, twist in the body frame (child_frame_id), as REP-105 says.
nav_msgs::msg::dds_::Odometry_ toOdometryMsg(const dataset::GroundTruthState& state, const std::string& world_frame,
                                             const std::string& body_frame);

/// The frontend's output as mcvio_msgs/FeatureFrame (frame id cam0, stamp = image time).
mcvio_msgs::msg::dds_::FeatureFrame_ toFeatureFrameMsg(const FeatureFrame& frame);
/// The inverse, for the backend side.
FeatureFrame fromFeatureFrameMsg(const mcvio_msgs::msg::dds_::FeatureFrame_& msg);

/// The estimator's pose as nav_msgs/Odometry: pose of `body_frame` in `world_frame`, twist in
/// `body_frame` (REP-105), `omega_B` the bias-corrected body rate [rad/s].
/// Pose covariance (row-major, x y z rot_x rot_y rot_z): the estimator's [dp world, dtheta body]
/// with the rotation part turned into world axes (q = Exp(dtheta_W) q_hat, dtheta_W = R dtheta_B),
/// as ROS consumers (robot_localization, RViz) read it. When the estimator has no covariance,
/// pose.covariance[0] = -1. The estimator does not estimate a velocity covariance:
/// twist.covariance[0] = -1 always, the sensor_msgs convention for "unknown"; fusion nodes must
/// not fuse this twist as if it were certain.
nav_msgs::msg::dds_::Odometry_ toOdometryMsg(const estimator::EstimatorOutput& estimate, const Eigen::Vector3d& omega_B,
                                             const std::string& world_frame, const std::string& body_frame);
/// The conflicting frame S of a motion conflict (ConflictReport::p_WS, q_WS, v_WS) as
/// nav_msgs/Odometry in `world_frame` with child `secondary_frame`; covariances unknown (-1).
nav_msgs::msg::dds_::Odometry_ toSecondaryOdometryMsg(const estimator::EstimatorOutput& estimate,
                                                      const std::string& world_frame,
                                                      const std::string& secondary_frame);
/// One pose of a trajectory (for toPathMsg).
struct StampedPose {
  Timestamp t = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};
/// nav_msgs/Path in `frame_id`, stamped with the newest pose (or 0 when empty).
nav_msgs::msg::dds_::Path_ toPathMsg(const std::vector<StampedPose>& poses, const std::string& frame_id);
/// One transform parent -> child (p_parent = T * p_child) at time t.
geometry_msgs::msg::dds_::TransformStamped_ toTransformStamped(const Eigen::Isometry3d& T_parent_child, Timestamp t,
                                                               const std::string& parent, const std::string& child);
tf2_msgs::msg::dds_::TFMessage_ toTfMessage(const std::vector<geometry_msgs::msg::dds_::TransformStamped_>& transforms);
/// Points as sensor_msgs/PointCloud2: one row, fields x y z float32 at offsets 0 4 8, point_step
/// 12, little endian; non-finite points are left out (is_dense true).
sensor_msgs::msg::dds_::PointCloud2_ toPointCloud2Msg(const std::vector<Eigen::Vector3d>& points, Timestamp t,
                                                      const std::string& frame_id);
/// ConflictReport as mcvio_msgs/MotionConflict (header stamp = frame time, frame `world_frame`).
mcvio_msgs::msg::dds_::MotionConflict_ toMotionConflictMsg(const estimator::EstimatorOutput& estimate,
                                                           const std::string& world_frame);

}  // namespace mcvio::components
