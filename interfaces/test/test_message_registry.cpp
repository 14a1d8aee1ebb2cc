#include <gtest/gtest.h>

#include <regex>

#include "mcvio/interfaces/message_registry.hpp"
#include "mcvio/interfaces/type_names.hpp"

using mcvio::interfaces::MessageRegistry;

// Hashes published by ROS 2 Jazzy for these types (REP-2011 RIHS01): ours must be identical or
// Jazzy tools reject our writers' typehash.
TEST(MessageRegistry, TypeHashesMatchRos2Jazzy) {
  EXPECT_EQ(MessageRegistry::get("std_msgs/msg/String").type_hash,
            "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18");
  EXPECT_EQ(MessageRegistry::get("std_msgs/msg/Header").type_hash,
            "RIHS01_f49fb3ae2cf070f793645ff749683ac6b06203e41c891e17701b1cb597ce6a01");
  EXPECT_EQ(MessageRegistry::get("geometry_msgs/msg/PoseStamped").type_hash,
            "RIHS01_10f3786d7d40fd2b54367835614bff85d4ad3b5dab62bf8bca0cc232d73b4cd8");
  EXPECT_EQ(MessageRegistry::get("sensor_msgs/msg/Imu").type_hash,
            "RIHS01_7d9a00ff131080897a5ec7e26e315954b8eae3353c3f995c55faf71574000b5b");
  EXPECT_EQ(MessageRegistry::get("nav_msgs/msg/Odometry").type_hash,
            "RIHS01_3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0");
}

TEST(MessageRegistry, EveryTypeHasTextDefinitionAndHash) {
  const std::regex hash("RIHS01_[0-9a-f]{64}");
  ASSERT_GE(MessageRegistry::all().size(), 27u);
  for (const auto& d : MessageRegistry::all()) {
    EXPECT_FALSE(d.text.empty()) << d.name;
    EXPECT_EQ(d.full_definition.substr(0, d.text.size() - 1), d.text.substr(0, d.text.size() - 1))
        << d.name;
    EXPECT_TRUE(std::regex_match(std::string(d.type_hash), hash)) << d.name;
  }
}

TEST(MessageRegistry, FullDefinitionAppendsDependenciesTheRosbag2Way) {
  const auto& odom = MessageRegistry::get("nav_msgs/msg/Odometry");
  const std::string sep = std::string(80, '=') + "\nMSG: ";
  for (const char* dep : {"std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/PoseWithCovariance",
                          "geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion",
                          "geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist",
                          "geometry_msgs/Vector3"}) {
    EXPECT_NE(odom.full_definition.find(sep + dep + "\n"), std::string_view::npos) << dep;
  }
  // Each dependency appears once.
  EXPECT_EQ(odom.full_definition.find(sep + "geometry_msgs/Vector3\n"),
            odom.full_definition.rfind(sep + "geometry_msgs/Vector3\n"));
}

TEST(MessageRegistry, UnknownTypeIsNamedInTheError) {
  EXPECT_EQ(MessageRegistry::find("foo_msgs/msg/Bar"), nullptr);
  try {
    MessageRegistry::get("foo_msgs/msg/Bar");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("foo_msgs/msg/Bar"), std::string::npos);
  }
}

TEST(TypeNames, RosAndDdsNamesConvertBothWays) {
  using namespace mcvio::interfaces;
  EXPECT_EQ(rosToDdsTypeName("sensor_msgs/msg/Image"), "sensor_msgs::msg::dds_::Image_");
  EXPECT_EQ(ddsToRosTypeName("sensor_msgs::msg::dds_::Image_"), "sensor_msgs/msg/Image");
  EXPECT_EQ(ddsToRosTypeName("rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"),
            "rmw_dds_common/msg/ParticipantEntitiesInfo");
  EXPECT_FALSE(ddsToRosTypeName("HelloWorld").has_value());
  EXPECT_FALSE(ddsToRosTypeName("a::b::c::dds_::X_").has_value());
  EXPECT_THROW(rosToDdsTypeName("Image"), std::invalid_argument);
  EXPECT_THROW(rosToDdsTypeName("sensor_msgs/Image"), std::invalid_argument);
  EXPECT_THROW(rosToDdsTypeName("a/b/c/d"), std::invalid_argument);
}
