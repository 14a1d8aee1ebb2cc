#include "mcvio/core/topic_remapping.hpp"

#include <gtest/gtest.h>

#include "input_error_message.hpp"
#include "mcvio/core/ros_topic_name.hpp"

namespace mcvio {
namespace {

using test::errorOf;

TEST(TopicRemapping, ResolvesRemappedNamesAndLeavesTheOthers) {
  const auto r = TopicRemapping::parse({"/cam0/image_raw:=/camera/infra1/image_rect_raw", "imu0:=camera/imu"});
  EXPECT_EQ(r.resolve("/cam0/image_raw"), "/camera/infra1/image_rect_raw");
  EXPECT_EQ(r.resolve("cam0/image_raw"), "/camera/infra1/image_rect_raw");  // relative is absolute in mcvio
  EXPECT_EQ(r.resolve("/imu0"), "/camera/imu");
  EXPECT_EQ(r.resolve("/cam1/image_raw"), "/cam1/image_raw");
  EXPECT_EQ(r.resolve("mcvio/features"), "/mcvio/features");
  // Rules apply once: the target of one rule is not remapped again by another.
  const auto chain = TopicRemapping::parse({"/a:=/b", "/b:=/c"});
  EXPECT_EQ(chain.resolve("/a"), "/b");
  EXPECT_EQ(chain.resolve("/b"), "/c");
  EXPECT_EQ(r.toStrings(), (std::vector<std::string>{"/cam0/image_raw:=/camera/infra1/image_rect_raw", "/imu0:=/camera/imu"}));
  EXPECT_TRUE(TopicRemapping().empty());
  EXPECT_EQ(TopicRemapping().resolve("imu0"), "/imu0");
}

TEST(TopicRemapping, BadRulesAreRefusedWithTheRuleNamed) {
  auto error = [](std::vector<std::string> rules) { return errorOf([&] { TopicRemapping::parse(rules); }); };
  EXPECT_EQ(error({"/imu0"}), "remap rule '/imu0': expected FROM:=TO, e.g. /imu0:=/camera/imu");
  EXPECT_EQ(error({"/imu0:="}), "remap rule '/imu0:=': '': topic name is empty");
  EXPECT_EQ(error({":=/camera/imu"}), "remap rule ':=/camera/imu': '': topic name is empty");
  EXPECT_EQ(error({"/imu0:=/camera imu"}),
            "remap rule '/imu0:=/camera imu': '/camera imu': topic name contains ' ' at position 7 (allowed: letters, "
            "digits, '_' and '/')");
  EXPECT_EQ(error({"/imu0:=/a", "imu0:=/b"}), "remap rule 'imu0:=/b': /imu0 is remapped twice (to /a and to /b)");
  EXPECT_EQ(error({"__node:=frontend2"}),
            "remap rule '__node:=frontend2': '__node' is a node-name or namespace rule; mcvio remaps topic names only");
  EXPECT_EQ(error({"frontend:/imu0:=/camera/imu"}),
            "remap rule 'frontend:/imu0:=/camera/imu': 'frontend:/imu0' holds a ':'; node-specific rules "
            "(NODE:FROM:=TO) are not supported, give the rule to that component");
  EXPECT_EQ(error({"/a:=/b:=/c"}), "remap rule '/a:=/b:=/c': '/b:=/c' holds a ':'; node-specific rules "
                                   "(NODE:FROM:=TO) are not supported, give the rule to that component");
}

TEST(RosTopicName, FollowsTheRosRules) {
  EXPECT_EQ(rosTopicNameError("/cam0/image_raw"), "");
  EXPECT_EQ(rosTopicNameError("cam0/image_raw"), "");
  EXPECT_NE(rosTopicNameError(""), "");
  EXPECT_NE(rosTopicNameError("/a//b"), "");
  EXPECT_NE(rosTopicNameError("/a/"), "");
  EXPECT_NE(rosTopicNameError("/0a"), "");
  EXPECT_NE(rosTopicNameError("/a b"), "");
  EXPECT_EQ(absoluteTopicName("a/b"), "/a/b");
  EXPECT_EQ(absoluteTopicName("/a/b"), "/a/b");
}

}  // namespace
}  // namespace mcvio
