#pragma once
#include <cstdint>
#include <string>

namespace mcvio::dds {

/// The QoS settings ROS 2 users reason about, with presets mirroring rclcpp's.
struct QosProfile {
  enum class Reliability : std::uint8_t { kReliable, kBestEffort };
  enum class Durability : std::uint8_t { kVolatile, kTransientLocal };
  enum class History : std::uint8_t { kKeepLast, kKeepAll };

  Reliability reliability = Reliability::kReliable;
  Durability durability = Durability::kVolatile;
  History history = History::kKeepLast;
  std::int32_t depth = 10;
  /// Use the topic name as the DDS topic, without ROS 2's "rt" prefix (as rclcpp's option of the
  /// same name); for DDS-level topics such as ros_discovery_info.
  bool avoid_ros_namespace_conventions = false;

  /// Best effort, keep last 5: cameras and IMUs, where fresh beats complete (rclcpp SensorDataQoS).
  static QosProfile sensorData() { return {Reliability::kBestEffort, Durability::kVolatile, History::kKeepLast, 5, false}; }
  /// Reliable, keep last 10 (rclcpp's default).
  static QosProfile defaults() { return {}; }
  /// Reliable, keep all: offline playback and recording, where nothing may be lost; a full
  /// reader history makes the writer wait instead of dropping.
  static QosProfile lossless() { return {Reliability::kReliable, Durability::kVolatile, History::kKeepAll, 0, false}; }
  /// Reliable, transient local, keep last `depth`: late joiners get the last samples
  /// (calibration, /tf_static, the path).
  static QosProfile transientLocal(std::int32_t depth = 1) {
    return {Reliability::kReliable, Durability::kTransientLocal, History::kKeepLast, depth, false};
  }

  /// One entry of rosbag2's `offered_qos_profiles` YAML list (without the leading "- ").
  std::string toRosbag2Yaml() const;
  /// "reliable, transient_local, keep_last(1)"
  std::string describe() const;

  bool operator==(const QosProfile& o) const {
    return reliability == o.reliability && durability == o.durability && history == o.history && depth == o.depth;
  }
};

}  // namespace mcvio::dds
