#pragma once
#include <string>

namespace mcvio::bag {

/// A recorded topic as rosbag2 describes it, plus the message definition that MCAP embeds as
/// schema. Every field is stored as given; nothing is derived from the type name.
struct TopicInfo {
  std::string name;                          ///< ROS topic name, e.g. "/imu0".
  std::string type;                          ///< ROS type, e.g. "sensor_msgs/msg/Imu".
  std::string serialization_format = "cdr";  ///< rosbag2 serialization format; CDR for ROS 2.
  std::string offered_qos_profiles;          ///< YAML list of QoS profiles as rosbag2 writes it.
  /// The type's .msg text followed by each nested type after a line of 80 '=' and
  /// "MSG: pkg/Name" (rosbag2's ros2msg encoding). Empty for types without fields.
  std::string message_definition;
  std::string type_description_hash;  ///< "RIHS01_<hex>" (ROS 2 Iron and later), or empty.
};

}  // namespace mcvio::bag
