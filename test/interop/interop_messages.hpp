#pragma once
// The messages the interop talker publishes, and their JSON form for the Node.js peer.

#include <string>

#include "geometry_msgs/msg/TransformStamped.h"
#include "nav_msgs/msg/Odometry.h"
#include "sensor_msgs/msg/CameraInfo.h"
#include "sensor_msgs/msg/Image.h"
#include "sensor_msgs/msg/Imu.h"
#include "tf2_msgs/msg/TFMessage.h"

namespace mcvio::interop {

/// The talker also subscribes (std_msgs/msg/String) so the peer can check how a reader appears.
inline constexpr const char* kCommandTopic = "/interop/command";

/// One deterministic message per interop topic. Every field holds a non-default value (so a field
/// the wire drops or shifts cannot compare equal by accident) and the doubles are not short
/// decimals (so the JSON has to carry all 17 significant digits).
struct InteropMessages {
  sensor_msgs::msg::dds_::Image_ image;             ///< /interop/image, 752x480 mono8 pattern
  sensor_msgs::msg::dds_::Imu_ imu;                 ///< /interop/imu
  sensor_msgs::msg::dds_::CameraInfo_ camera_info;  ///< /interop/camera_info, plumb_bob
  nav_msgs::msg::dds_::Odometry_ odometry;          ///< /interop/odometry
  tf2_msgs::msg::dds_::TFMessage_ tf;               ///< /tf, two transforms

  /// Builds the messages; the same call always gives the same messages.
  static InteropMessages make();

  /// The peer's expected-messages document: {"node_namespace", "node_name", "participant_gid",
  /// "topics": [{"name", "type", "message"}], "subscriptions": [{"name", "type"}]}, ROS field names,
  /// doubles printed with 17
  /// significant digits, byte arrays as arrays of numbers. `participant_gid` is the hex of the
  /// publishing participant's 16-byte ROS 2 GID, so the peer ignores other participants.
  std::string toJson(const std::string& node_namespace, const std::string& node_name,
                     const std::string& participant_gid) const;
};

}  // namespace mcvio::interop
