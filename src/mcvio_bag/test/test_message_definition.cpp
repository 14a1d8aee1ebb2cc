#include <gtest/gtest.h>

#include "bag_test_util.hpp"
#include "mcvio/bag/message_definition.hpp"
#include "mcvio/core/input_error.hpp"

namespace mcvio::bag {
namespace {

TEST(MessageDefinition, ParsesPoseStampedWithNestedTypes) {
  const auto types =
      MessageDefinitionParser::parse("geometry_msgs/msg/PoseStamped", test::kPoseStampedDefinition);
  ASSERT_EQ(types.size(), 6u);
  EXPECT_EQ(types[0].fields.size(), 2u);
  EXPECT_EQ(types[0].fields[0].type, "std_msgs/Header");
  EXPECT_TRUE(types[0].fields[0].is_complex);
  EXPECT_EQ(types[0].fields[1].type, "geometry_msgs/Pose");  // "Pose" in the same package
  EXPECT_EQ(types[5].name, "geometry_msgs/Quaternion");
  EXPECT_EQ(types[5].fields[3].value, "1");
}

TEST(MessageDefinition, ArraysConstantsAndBounds) {
  const auto t = MessageDefinitionParser::parse(
      "p/msg/T",
      "uint8 A=3 # comment\nstring S=hello # kept\nfloat64[9] cov\nint32[] v\nint8[<=4] b\n"
      "string<=10 name\nbyte x 7\n");
  const auto& f = t[0].fields;
  ASSERT_EQ(f.size(), 7u);
  EXPECT_TRUE(f[0].is_constant);
  EXPECT_EQ(f[0].value, "3");
  EXPECT_EQ(f[1].value, "hello # kept");
  EXPECT_EQ(f[2].array_length, 9u);
  EXPECT_TRUE(f[3].is_array);
  EXPECT_EQ(f[3].array_length, 0u);
  EXPECT_TRUE(f[4].is_bounded);
  EXPECT_EQ(f[5].string_bound, 10u);
  EXPECT_EQ(f[6].value, "7");
  EXPECT_TRUE(MessageDefinitionParser::parse("std_msgs/msg/Empty", "").at(0).fields.empty());
}

TEST(MessageDefinition, RejectsWhatADecoderCannotUse) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"geometry_msgs/Point position\n", "whose definition is not included"},
      {"float64[x] a\n", "bad array length"},
      {"float64\n", "missing or invalid field name"},
      {"float64 a\nfloat64 a\n", "duplicate field name"},
      {"int32 a\n===\nint32 b\n", "expected 'MSG: pkg/Name'"},
      {"int32 a\n=====\n", "separator line without"},
      {"string<=x s\n", "bad bounded type"},
      {"int32[] C=4\n", "must be a primitive"},
      {"ns/sub/x/Y a\n", "malformed type"},
  };
  for (const auto& [text, why] : bad) {
    try {
      MessageDefinitionParser::parse("p/msg/T", text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("p/msg/T"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace mcvio::bag
