#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mcvio/core/time.hpp"

namespace mcvio::bag {

/// One serialized message as stored in a bag: the payload is the CDR bytes as received.
struct BagMessage {
  std::string topic;
  Timestamp log_time = 0;      ///< Receive (recording) time, ns since the Unix epoch.
  Timestamp publish_time = 0;  ///< Publish/header time, ns; equals log_time when unknown.
  std::uint32_t sequence = 0;  ///< Per-topic counter assigned by the writer.
  std::vector<std::uint8_t> data;
};

}  // namespace mcvio::bag
