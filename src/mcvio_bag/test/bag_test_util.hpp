#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mcvio/bag/bag_info.hpp"
#include "mcvio/bag/bag_message.hpp"
#include "mcvio/bag/topic_info.hpp"

namespace mcvio::bag::test {

/// std_msgs/msg/String's definition.
extern const char* const kStringDefinition;
/// geometry_msgs/msg/PoseStamped with every nested type, as rosbag2 embeds it.
extern const char* const kPoseStampedDefinition;

TopicInfo stringTopic(const std::string& name);
TopicInfo poseStampedTopic(const std::string& name);
/// A fresh, empty directory path (not created) unique to this process and `name`.
std::filesystem::path freshPath(const std::string& name);
/// Deterministic payload bytes for message `i` of `size` bytes.
std::vector<std::uint8_t> payload(std::uint64_t i, std::size_t size);
/// Reads every message of a bag.
std::vector<BagMessage> readAll(const std::filesystem::path& bag);
/// `bag info --verify`: bagInfo() reading every message; its warnings go to `warnings`.
BagVerification verifyBag(const std::filesystem::path& bag,
                          std::vector<std::string>* warnings = nullptr);
/// The warning lines that send the user to `mcvio bag reindex` (not those saying it cannot
/// help).
std::vector<std::string> reindexAdvice(const std::vector<std::string>& warnings);

}  // namespace mcvio::bag::test
