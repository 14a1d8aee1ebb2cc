#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace mcvio::interfaces {

/// What mcvio knows about one ROS 2 message type, built in from interfaces/msg at compile time.
struct MessageDescription {
  std::string_view name;             ///< ROS 2 name, e.g. "sensor_msgs/msg/Image"
  std::string_view text;             ///< the type's own .msg text
  std::string_view full_definition;  ///< .msg text plus its dependencies, as rosbag2 embeds it
  std::string_view type_hash;        ///< REP-2011 hash, "RIHS01_<64 hex>"
};

/// Lookup of the built-in message types by ROS 2 name ("pkg/msg/Name").
/// Bags embed full_definition as their schema; writers announce type_hash in user_data.
class MessageRegistry {
 public:
  /// The description of `ros_type`, or nullptr when mcvio does not know the type.
  static const MessageDescription* find(std::string_view ros_type);
  /// Like find(), but throws std::invalid_argument naming the type and listing the known ones.
  static const MessageDescription& get(std::string_view ros_type);
  /// Every built-in type, sorted by name.
  static const std::vector<MessageDescription>& all();
};

}  // namespace mcvio::interfaces
