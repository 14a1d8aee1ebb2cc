#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace mcvio::bag {

/// One line of a .msg definition: a field or a constant.
struct MessageField {
  std::string type;  ///< Base type: a primitive ("float64", "string") or "pkg/Name".
  std::string name;
  bool is_complex = false;  ///< A nested message type.
  bool is_array = false;
  std::size_t array_length = 0;  ///< Fixed length, or the bound of "[<=N]"; 0 if unbounded.
  bool is_bounded = false;       ///< "[<=N]".
  std::size_t string_bound = 0;  ///< N of "string<=N"; 0 if unbounded.
  bool is_constant = false;
  std::string value;  ///< Constant value or default value text.
};

/// One message type of a definition: the root type first, then each nested type.
struct MessageType {
  std::string name;  ///< "pkg/msg/Name" for the root as given; "pkg/Name" for nested sections.
  std::vector<MessageField> fields;
};

/// Parses and checks rosbag2's `ros2msg` schema text: the root type's .msg text, then for each
/// nested type a line of '=' and "MSG: pkg/Name" followed by its text. A definition that a
/// ROS 2 decoder could not use (bad syntax, unknown nested type) throws mcvio::InputError whose
/// message names the type and line.
class MessageDefinitionParser {
 public:
  static std::vector<MessageType> parse(const std::string& type_name, const std::string& text);
};

}  // namespace mcvio::bag
