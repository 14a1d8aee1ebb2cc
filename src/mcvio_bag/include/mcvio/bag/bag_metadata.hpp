#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "mcvio/bag/topic_info.hpp"
#include "mcvio/core/time.hpp"

namespace mcvio::bag {

/// A topic and how many messages of it the bag holds (rosbag2's topics_with_message_count).
struct TopicInformation {
  TopicInfo topic;  ///< message_definition is not part of metadata.yaml and stays empty there.
  std::uint64_t message_count = 0;
};

/// One storage file (rosbag2's `files` entry, metadata version 5 and later).
struct FileInformation {
  std::string path;  ///< Relative to the bag directory.
  Timestamp starting_time = 0;
  Timestamp duration = 0;
  std::uint64_t message_count = 0;
};

/// The content of a rosbag2 `metadata.yaml` (key rosbag2_bagfile_information).
struct BagMetadata {
  /// Written as 8: the field set below, offered_qos_profiles as a YAML string (Iron's layout).
  int version = 8;
  std::string storage_identifier = "mcap";  ///< "mcap" or "sqlite3".
  Timestamp duration = 0;
  Timestamp starting_time = 0;
  std::uint64_t message_count = 0;
  std::vector<TopicInformation> topics_with_message_count;
  std::string compression_format;  ///< rosbag2 file/message compression ("" for MCAP chunks).
  std::string compression_mode;    ///< "", "FILE" or "MESSAGE".
  std::vector<std::string> relative_file_paths;
  std::vector<FileInformation> files;
  std::map<std::string, std::string> custom_data;
  std::string ros_distro;
};

/// Oldest metadata.yaml version read (the first with the `files` list).
inline constexpr int kMinMetadataVersion = 5;
inline constexpr const char* kMetadataFileName = "metadata.yaml";

/// Serializes to rosbag2's YAML layout.
std::string bagMetadataToYaml(const BagMetadata& metadata);
/// Parses rosbag2 YAML (versions 5..9); `source` names the file in InputError messages.
BagMetadata bagMetadataFromYaml(const std::string& yaml, const std::string& source);
/// Reads `<bag_dir>/metadata.yaml`; InputError when missing or malformed.
BagMetadata readBagMetadata(const std::filesystem::path& bag_dir);
/// Writes `<bag_dir>/metadata.yaml` atomically (temporary file, then rename).
void writeBagMetadata(const std::filesystem::path& bag_dir, const BagMetadata& metadata);

}  // namespace mcvio::bag
