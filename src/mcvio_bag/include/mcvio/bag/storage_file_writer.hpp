#pragma once
#include <cstddef>
#include <cstdint>

#include "mcvio/bag/topic_info.hpp"
#include "mcvio/core/time.hpp"

namespace mcvio::bag {

/// One storage file of a bag being written (an .mcap or a .db3). BagWriter owns one at a time
/// and moves to a new one when it splits.
class StorageFileWriter {
 public:
  virtual ~StorageFileWriter() = default;
  /// Registers topic number `topic_index` (dense, from 0, in registration order).
  virtual void addTopic(std::size_t topic_index, const TopicInfo& topic) = 0;
  /// Appends one message; buffers it and persists it when its chunk/transaction fills.
  virtual void write(std::size_t topic_index, Timestamp log_time, Timestamp publish_time,
                     std::uint32_t sequence, const std::uint8_t* data, std::size_t size) = 0;
  /// Persists every buffered message (a complete chunk / a committed transaction).
  virtual void flush() = 0;
  /// Bytes the file will hold once buffered data is flushed (used to split by size).
  virtual std::uint64_t sizeBytes() const = 0;
  /// Flushes and finishes the file (summary, indexes). Idempotent.
  virtual void close() = 0;
};

}  // namespace mcvio::bag
