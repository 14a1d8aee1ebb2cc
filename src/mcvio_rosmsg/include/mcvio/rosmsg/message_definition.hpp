#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace mcvio::rosmsg {

/// Primitive kinds of the ROS 2 interface language; kNested is a field of another message type.
enum class FieldKind : std::uint8_t {
  kBool, kByte, kChar, kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kInt64, kUint64,
  kFloat32, kFloat64, kString, kWString, kNested
};

/// One field of a message: `uint8[16] data`, `string<=256 node_name`, `Pose[] poses`.
struct FieldDefinition {
  std::string name;
  FieldKind kind = FieldKind::kInt32;
  std::string nested_type;     ///< "pkg/msg/Name" when kind == kNested
  std::uint32_t string_bound = 0;
  enum class Array : std::uint8_t { kNone, kFixed, kBounded, kUnbounded } array = Array::kNone;
  std::uint32_t array_size = 0;  ///< element count (kFixed) or bound (kBounded)
};

/// One message type's fields, in wire order.
struct MessageDefinition {
  std::string name;  ///< "pkg/msg/Name"
  std::vector<FieldDefinition> fields;
};

/// A message type together with every type it uses, parsed from .msg text in the form rosbag2
/// stores as an MCAP schema (the main text, then per dependency a line of '=' and `MSG: pkg/Name`).
class MessageDefinitionSet {
 public:
  /// Parses `full_definition` for `root_type` ("pkg/msg/Name"). Throws mcvio::InputError naming the
  /// type and line when the text does not parse or a used type is not defined.
  static MessageDefinitionSet parse(std::string_view root_type, std::string_view full_definition);

  const MessageDefinition& root() const { return types_.at(root_); }
  /// The definition of a nested type; throws mcvio::InputError when it is absent.
  const MessageDefinition& type(const std::string& name) const;

 private:
  std::string root_;
  std::map<std::string, MessageDefinition> types_;
};

/// Size in bytes of a primitive on the CDR wire (0 for strings and nested types).
std::size_t primitiveSize(FieldKind kind);

}  // namespace mcvio::rosmsg
