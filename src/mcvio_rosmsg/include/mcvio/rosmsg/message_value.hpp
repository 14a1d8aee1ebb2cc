#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace mcvio::rosmsg {

/// A decoded message as a tree, for printing (`mcvio echo`) and generic comparison.
/// Integers keep their sign, floating point values are doubles; byte arrays stay compact.
struct MessageValue {
  using Fields = std::vector<std::pair<std::string, MessageValue>>;
  using Array = std::vector<MessageValue>;
  using Bytes = std::vector<std::uint8_t>;
  std::variant<bool, std::int64_t, std::uint64_t, double, std::string, Bytes, Array, Fields> value;

  bool operator==(const MessageValue& other) const { return value == other.value; }
  /// The field called `name` of a message value; throws std::out_of_range when absent.
  const MessageValue& operator[](const std::string& name) const;
};

}  // namespace mcvio::rosmsg
