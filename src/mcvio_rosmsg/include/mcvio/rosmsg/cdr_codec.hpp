#pragma once
#include <cstdint>
#include <vector>

#include "mcvio/rosmsg/message_definition.hpp"
#include "mcvio/rosmsg/message_value.hpp"

namespace mcvio::rosmsg {

/// Plain CDR (XCDR1, as ROS 2 uses) driven by a parsed definition, so any type can be decoded
/// without generated code. Payloads start with the 4-byte encapsulation header.
class CdrCodec {
 public:
  explicit CdrCodec(const MessageDefinitionSet& definitions) : defs_(definitions) {}

  /// Decodes a serialized payload. Throws mcvio::InputError naming the field and byte offset when
  /// the payload is truncated, has an unknown encapsulation or an absurd length.
  MessageValue decode(const std::uint8_t* data, std::size_t size) const;
  MessageValue decode(const std::vector<std::uint8_t>& payload) const {
    return decode(payload.data(), payload.size());
  }

  /// Encodes a value tree of the root type (little endian). Throws std::invalid_argument when the
  /// tree does not fit the definition.
  std::vector<std::uint8_t> encode(const MessageValue& value) const;

 private:
  const MessageDefinitionSet& defs_;
};

}  // namespace mcvio::rosmsg
