#include <gtest/gtest.h>

#include "mcvio/dds/qos_profile.hpp"
#include "mcvio/dds/topic_names.hpp"

using namespace mcvio::dds;

TEST(TopicNames, RosTopicsMapToRtPrefixedDdsTopics) {
  EXPECT_EQ(toDdsTopicName("/cam0/image_raw"), "rt/cam0/image_raw");
  EXPECT_EQ(toDdsTopicName("mcvio/odometry"), "rt/mcvio/odometry");
  EXPECT_EQ(toRosTopicName("rt/tf"), "/tf");
  EXPECT_FALSE(toRosTopicName("ros_discovery_info").has_value());
  EXPECT_FALSE(toRosTopicName("rq/add_two_intsRequest").has_value());
}

TEST(TopicNames, InvalidNamesAreRejectedWithTheReason) {
  struct Case { const char* name; const char* reason; };
  for (const Case& c : {Case{"", "empty"}, Case{"/a//b", "'//'"}, Case{"/a/", "end with '/'"},
                        Case{"/cam0/1image", "digit"}, Case{"/cam 0", "' '"}, Case{"/a-b", "'-'"},
                        Case{"/", "no tokens"}}) {
    try {
      validateTopicName(c.name);
      ADD_FAILURE() << "accepted '" << c.name << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(c.reason), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::string("'") + c.name + "'"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(validateTopicName(std::string(300, 'a')), std::invalid_argument);
  EXPECT_NO_THROW(validateTopicName("/mcvio/secondary_odometry"));
  EXPECT_NO_THROW(validateTopicName("/tf_static"));
}

TEST(TopicNames, NodeNames) {
  EXPECT_NO_THROW(validateNodeName("backend"));
  EXPECT_NO_THROW(validateNodeName("mcvio_frontend_2"));
  EXPECT_THROW(validateNodeName(""), std::invalid_argument);
  EXPECT_THROW(validateNodeName("2fast"), std::invalid_argument);
  EXPECT_THROW(validateNodeName("front/end"), std::invalid_argument);
}

TEST(QosProfile, PresetsMirrorRos2) {
  EXPECT_EQ(QosProfile::sensorData().reliability, QosProfile::Reliability::kBestEffort);
  EXPECT_EQ(QosProfile::sensorData().depth, 5);
  EXPECT_EQ(QosProfile::defaults().reliability, QosProfile::Reliability::kReliable);
  EXPECT_EQ(QosProfile::defaults().depth, 10);
  EXPECT_EQ(QosProfile::lossless().history, QosProfile::History::kKeepAll);
  EXPECT_EQ(QosProfile::transientLocal().durability, QosProfile::Durability::kTransientLocal);
  EXPECT_EQ(QosProfile::transientLocal().describe(), "reliable, transient_local, keep_last(1)");
  const auto y = QosProfile::sensorData().toRosbag2Yaml();
  EXPECT_NE(y.find("reliability: 2"), std::string::npos) << y;
  EXPECT_NE(y.find("depth: 5"), std::string::npos) << y;
}
