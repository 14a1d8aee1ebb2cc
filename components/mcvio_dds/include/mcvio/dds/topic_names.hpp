#pragma once
#include <optional>
#include <string>
#include <string_view>

namespace mcvio::dds {

/// ROS 2 name rules, so what we publish is addressable from `ros2 topic echo`.
/// Returns an empty string when `name` is a valid fully-qualified topic name ("/a/b"), otherwise
/// a sentence saying what is wrong. Relative names ("a/b") are valid and mean "/a/b".
std::string topicNameError(std::string_view name);

/// Throws std::invalid_argument with topicNameError()'s sentence and the name.
void validateTopicName(std::string_view name);

/// Valid node names: letters, digits and '_', not starting with a digit. Throws otherwise.
void validateNodeName(std::string_view name);

/// "/cam0/image_raw" or "cam0/image_raw" -> "rt/cam0/image_raw" (the DDS topic ROS 2 uses).
std::string toDdsTopicName(std::string_view ros_topic);

/// "rt/cam0/image_raw" -> "/cam0/image_raw"; nullopt for DDS topics that are not ROS 2 topics
/// (services "rq/…", "rr/…", or plain DDS applications).
std::optional<std::string> toRosTopicName(std::string_view dds_topic);

}  // namespace mcvio::dds
