#pragma once
#include <string>

#include <opencv2/core.hpp>

#include "mcvio/core/camera_calibration.hpp"
#include "mcvio/core/feature_frame.hpp"
#include "mcvio/core/imu_sample.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"
#include "mcvio/interfaces/ros_type_traits.hpp"

namespace mcvio::components {

/// Between mcvio's plain structs and the ROS 2 messages on the bus. Stamps are the data's own
/// int64 nanoseconds, so a bag or a subscriber sees the dataset's time.
std_msgs::msg::dds_::Header_ makeHeader(Timestamp t, const std::string& frame_id);
Timestamp stampOf(const std_msgs::msg::dds_::Header_& header);

/// mono8 image; throws std::invalid_argument for a cv::Mat that is not CV_8UC1.
sensor_msgs::msg::dds_::Image_ toImageMsg(const cv::Mat& image, Timestamp t, const std::string& frame_id);
sensor_msgs::msg::dds_::Imu_ toImuMsg(const ImuSample& sample, const std::string& frame_id);
/// plumb_bob for radial-tangential, "equidistant" for equidistant; R identity, P = [K | 0].
sensor_msgs::msg::dds_::CameraInfo_ toCameraInfoMsg(const CameraCalibration& calibration, Timestamp t);
/// Pose of the body in `world`, twist in the body frame (child_frame_id), as REP-105 says.
nav_msgs::msg::dds_::Odometry_ toOdometryMsg(const dataset::GroundTruthState& state, const std::string& world_frame,
                                             const std::string& body_frame);

/// The frontend's output as mcvio_msgs/FeatureFrame (frame id cam0, stamp = image time).
mcvio_msgs::msg::dds_::FeatureFrame_ toFeatureFrameMsg(const FeatureFrame& frame);
/// The inverse, for the backend side.
FeatureFrame fromFeatureFrameMsg(const mcvio_msgs::msg::dds_::FeatureFrame_& msg);

}  // namespace mcvio::components
