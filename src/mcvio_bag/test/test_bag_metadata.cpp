#include <gtest/gtest.h>

#include "mcvio/bag/bag_metadata.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {
namespace {

TEST(BagMetadata, YamlRoundTrip) {
  BagMetadata m;
  m.storage_identifier = "sqlite3";
  m.duration = 5;
  m.starting_time = 1700000000123456789;
  m.message_count = 7;
  TopicInformation t;
  t.topic.name = "/imu0";
  t.topic.type = "sensor_msgs/msg/Imu";
  t.topic.offered_qos_profiles = "- history: 1\n  depth: 10\n";
  t.topic.type_description_hash = "RIHS01_00";
  t.message_count = 7;
  m.topics_with_message_count.push_back(t);
  m.compression_format = "zstd";
  m.compression_mode = "MESSAGE";
  m.relative_file_paths = {"b_0.db3"};
  m.files.push_back({"b_0.db3", m.starting_time, 5, 7});
  m.custom_data["recorder"] = "mcvio";
  m.ros_distro = "jazzy";
  const std::string yaml = bagMetadataToYaml(m);
  EXPECT_NE(yaml.find("rosbag2_bagfile_information:"), std::string::npos);
  EXPECT_NE(yaml.find("nanoseconds_since_epoch: 1700000000123456789"), std::string::npos);
  const BagMetadata r = bagMetadataFromYaml(yaml, "x.yaml");
  EXPECT_EQ(r.version, 8);
  EXPECT_EQ(r.storage_identifier, "sqlite3");
  EXPECT_EQ(r.starting_time, m.starting_time);
  EXPECT_EQ(r.duration, 5);
  ASSERT_EQ(r.topics_with_message_count.size(), 1u);
  EXPECT_EQ(r.topics_with_message_count[0].topic.offered_qos_profiles,
            t.topic.offered_qos_profiles);
  EXPECT_EQ(r.topics_with_message_count[0].topic.type_description_hash, "RIHS01_00");
  EXPECT_EQ(r.files.at(0).message_count, 7u);
  EXPECT_EQ(r.custom_data.at("recorder"), "mcvio");
  EXPECT_EQ(r.ros_distro, "jazzy");
  EXPECT_EQ(r.compression_mode, "MESSAGE");
}

TEST(BagMetadata, ReadsVersion9QosListsAndRejectsOldVersions) {
  const std::string v9 =
      "rosbag2_bagfile_information:\n  version: 9\n  storage_identifier: mcap\n"
      "  duration:\n    nanoseconds: 10\n  starting_time:\n    nanoseconds_since_epoch: 3\n"
      "  message_count: 1\n  topics_with_message_count:\n    - topic_metadata:\n"
      "        name: /a\n        type: std_msgs/msg/String\n        serialization_format: cdr\n"
      "        offered_qos_profiles:\n          - history: keep_last\n            depth: 10\n"
      "        type_description_hash: RIHS01_ab\n      message_count: 1\n"
      "  compression_format: \"\"\n  compression_mode: \"\"\n  relative_file_paths:\n    - "
      "a_0.mcap\n"
      "  files:\n    - path: a_0.mcap\n      starting_time:\n        nanoseconds_since_epoch: 3\n"
      "      duration:\n        nanoseconds: 10\n      message_count: 1\n  custom_data: ~\n"
      "  ros_distro: rolling\n";
  const BagMetadata m = bagMetadataFromYaml(v9, "v9.yaml");
  EXPECT_NE(m.topics_with_message_count.at(0).topic.offered_qos_profiles.find("depth: 10"),
            std::string::npos);
  std::string v4 = v9;
  v4.replace(v4.find("version: 9"), 10, "version: 4");
  try {
    bagMetadataFromYaml(v4, "v4.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("v4.yaml: metadata version 4"), std::string::npos);
  }
  std::string bad = v9;
  bad.replace(bad.find("message_count: 1\n  topics"), 16, "message_count: x");
  try {
    bagMetadataFromYaml(bad, "bad.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rosbag2_bagfile_information.message_count"),
              std::string::npos)
        << e.what();
  }
  std::string escape = v9;
  escape.replace(escape.find("- a_0.mcap"), 10, "- ../x.mcap");
  EXPECT_THROW(bagMetadataFromYaml(escape, "e.yaml"), InputError);
}

}  // namespace
}  // namespace mcvio::bag
