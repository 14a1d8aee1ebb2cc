#include <gtest/gtest.h>

#include <cstring>

#include "mcvio/core/input_error.hpp"
#include "mcvio/rosmsg/cdr_codec.hpp"
#include "mcvio/rosmsg/message_definition.hpp"
#include "mcvio/rosmsg/yaml_printer.hpp"

using namespace mcvio::rosmsg;

namespace {

const char* kStampedDef =
    "# a test type\n"
    "uint8 KIND_A = 1\n"
    "std_msgs/Header header\n"
    "uint8 kind\n"
    "float64 value 2.5\n"
    "string<=8 tag\n"
    "int16[2] pair\n"
    "uint8[] blob\n"
    "geometry_msgs/Point[] points\n"
    "================================================================================\n"
    "MSG: std_msgs/Header\n"
    "builtin_interfaces/Time stamp\n"
    "string frame_id\n"
    "================================================================================\n"
    "MSG: builtin_interfaces/Time\n"
    "int32 sec\n"
    "uint32 nanosec\n"
    "================================================================================\n"
    "MSG: geometry_msgs/Point\n"
    "float64 x\nfloat64 y\nfloat64 z\n";

}  // namespace

TEST(MessageDefinition, ParsesFieldsConstantsBoundsAndDependencies) {
  auto set = MessageDefinitionSet::parse("test_msgs/msg/Stamped", kStampedDef);
  const auto& root = set.root();
  ASSERT_EQ(root.fields.size(), 7u);  // the constant is not a field
  EXPECT_EQ(root.fields[0].nested_type, "std_msgs/msg/Header");
  EXPECT_EQ(root.fields[3].string_bound, 8u);
  EXPECT_EQ(root.fields[4].array, FieldDefinition::Array::kFixed);
  EXPECT_EQ(root.fields[4].array_size, 2u);
  EXPECT_EQ(root.fields[5].array, FieldDefinition::Array::kUnbounded);
  EXPECT_EQ(set.type("std_msgs/msg/Header").fields[0].nested_type, "builtin_interfaces/msg/Time");
}

TEST(MessageDefinition, MissingDependencyIsNamed) {
  try {
    MessageDefinitionSet::parse("a/msg/B", "geometry_msgs/Pose pose\n");
    FAIL() << "expected an error";
  } catch (const mcvio::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("geometry_msgs/msg/Pose"), std::string::npos) << e.what();
  }
}

TEST(MessageDefinition, BadLineIsNamedWithItsNumber) {
  try {
    MessageDefinitionSet::parse("a/msg/B", "int32 ok\nfloat64[x] bad\n");
    FAIL() << "expected an error";
  } catch (const mcvio::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
}

TEST(CdrCodec, DecodesKnownBytesWithAlignment) {
  auto set = MessageDefinitionSet::parse("test_msgs/msg/Stamped", kStampedDef);
  CdrCodec codec(set);
  // Round-trip through encode to validate the hand layout logic independently.
  MessageValue v;
  v.value = MessageValue::Fields{
      {"header", MessageValue{MessageValue::Fields{
                     {"stamp", MessageValue{MessageValue::Fields{{"sec", MessageValue{std::int64_t{1}}},
                                                                  {"nanosec", MessageValue{std::uint64_t{2}}}}}},
                     {"frame_id", MessageValue{std::string("ab")}}}}},
      {"kind", MessageValue{std::uint64_t{7}}},
      {"value", MessageValue{-1.5}},
      {"tag", MessageValue{std::string("h")}},
      {"pair", MessageValue{MessageValue::Array{MessageValue{std::int64_t{-3}}, MessageValue{std::int64_t{4}}}}},
      {"blob", MessageValue{MessageValue::Bytes{9, 8, 7}}},
      {"points", MessageValue{MessageValue::Array{MessageValue{MessageValue::Fields{
                     {"x", MessageValue{1.0}}, {"y", MessageValue{2.0}}, {"z", MessageValue{3.0}}}}}}}};
  const auto enc = codec.encode(v);
  // Layout facts of plain CDR: the double starts at body offset 16 (8-aligned, no padding),
  // the string "h" follows at 24, the int16 pair at 30, the blob length at 36 (4-aligned).
  ASSERT_GE(enc.size(), 44u);
  EXPECT_EQ(enc[4 + 15], 7);
  double dv;
  std::memcpy(&dv, &enc[4 + 16], 8);
  EXPECT_EQ(dv, -1.5);
  EXPECT_EQ(enc[4 + 24], 2);   // length of "h" incl. NUL
  std::int16_t p0;
  std::memcpy(&p0, &enc[4 + 30], 2);
  EXPECT_EQ(p0, -3);
  EXPECT_EQ(enc[4 + 36], 3);   // blob length
  // Points: uint32 count at 44 (after 3 blob bytes at 40..42, padded), doubles at 48.
  EXPECT_EQ(enc[4 + 44], 1);
  double px;
  std::memcpy(&px, &enc[4 + 48], 8);
  EXPECT_EQ(px, 1.0);
  const auto dec = codec.decode(enc);
  EXPECT_EQ(dec, v);
  EXPECT_EQ(std::get<std::string>(dec["header"]["frame_id"].value), "ab");
}

TEST(CdrCodec, TruncatedPayloadNamesFieldAndOffset) {
  auto set = MessageDefinitionSet::parse("builtin_interfaces/msg/Time", "int32 sec\nuint32 nanosec\n");
  CdrCodec codec(set);
  const std::vector<std::uint8_t> b = {0x00, 0x01, 0x00, 0x00, 1, 0, 0, 0, 2, 0};
  try {
    codec.decode(b);
    FAIL() << "expected an error";
  } catch (const mcvio::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("nanosec"), std::string::npos) << m;
    EXPECT_NE(m.find("byte 8"), std::string::npos) << m;
  }
}

TEST(CdrCodec, AbsurdSequenceLengthIsRejectedWithoutAllocating) {
  auto set = MessageDefinitionSet::parse("a/msg/B", "float64[] values\n");
  CdrCodec codec(set);
  const std::vector<std::uint8_t> b = {0x00, 0x01, 0x00, 0x00, 0xff, 0xff, 0xff, 0x7f};
  EXPECT_THROW(codec.decode(b), mcvio::InputError);
}

TEST(CdrCodec, UnknownEncapsulationIsRejected) {
  auto set = MessageDefinitionSet::parse("a/msg/B", "int32 x\n");
  CdrCodec codec(set);
  const std::vector<std::uint8_t> b = {0x00, 0x07, 0x00, 0x00, 1, 0, 0, 0};  // XCDR2 PL
  EXPECT_THROW(codec.decode(b), mcvio::InputError);
}

TEST(CdrCodec, BigEndianPayloadDecodes) {
  auto set = MessageDefinitionSet::parse("a/msg/B", "int32 x\nfloat64 y\n");
  CdrCodec codec(set);
  std::vector<std::uint8_t> b = {0x00, 0x00, 0x00, 0x00, 0, 0, 1, 2, 0, 0, 0, 0};
  b.insert(b.end(), {0x3f, 0xf8, 0, 0, 0, 0, 0, 0});  // 1.5 big endian
  const auto v = codec.decode(b);
  EXPECT_EQ(std::get<std::int64_t>(v["x"].value), 258);
  EXPECT_EQ(std::get<double>(v["y"].value), 1.5);
}

TEST(YamlPrinter, PrintsNestedFieldsArraysAndTruncates) {
  MessageValue v;
  v.value = MessageValue::Fields{
      {"header", MessageValue{MessageValue::Fields{{"frame_id", MessageValue{std::string("cam0")}}}}},
      {"data", MessageValue{MessageValue::Bytes{1, 2, 3, 4}}},
      {"scale", MessageValue{2.0}}};
  const auto y = toYaml(v, YamlPrintOptions{2});
  EXPECT_EQ(y, "header:\n  frame_id: 'cam0'\ndata:\n- 1\n- 2\n- '... (2 more)'\nscale: 2.0\n");
}
