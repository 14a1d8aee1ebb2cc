#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "mcvio/bag/bag_message.hpp"
#include "mcvio/bag/topic_info.hpp"

namespace mcvio::bag {

/// Message counts and time range of one storage file.
struct FileStatistics {
  std::uint64_t message_count = 0;
  Timestamp start_time = 0;  ///< Earliest log time; 0 when the file has no messages.
  Timestamp end_time = 0;    ///< Latest log time.
  std::map<std::string, std::uint64_t> topic_message_counts;
};

/// Receives what StorageFileReader::verify() finds, message by message.
class VerifySink {
 public:
  virtual ~VerifySink() = default;
  /// One message of `topic` was read (and decompressed) intact.
  virtual void readable(const std::string& topic) = 0;
  /// `count` messages of `topic` ("" when the file no longer tells) cannot be read; `what`
  /// names the file, the place (row id or byte offset), the log time, why, and whether
  /// `mcvio bag reindex` can do anything about it.
  virtual void unreadable(const std::string& topic, std::uint64_t count,
                          const std::string& what) = 0;
  /// Damage that is not one topic's messages (e.g. the MCAP data section CRC).
  virtual void problem(const std::string& what) = 0;
};

/// One storage file of a bag being read (an .mcap or a .db3), yielding messages in log-time
/// order. Corrupt content throws mcvio::InputError naming the file and byte offset.
class StorageFileReader {
 public:
  virtual ~StorageFileReader() = default;
  /// Every topic the file declares, with its message definition when the file stores one.
  virtual const std::vector<TopicInfo>& topics() const = 0;
  /// Restricts next() to these topic names; empty means all. Call before the first next().
  virtual void setTopicFilter(const std::set<std::string>& topics) = 0;
  /// The next message in log-time order (ties in file order); false at the end.
  virtual bool next(BagMessage& out) = 0;
  virtual FileStatistics statistics() const = 0;
  /// Oddities that do not stop reading (e.g. an unknown sqlite3 schema version or a topic
  /// whose serialization format is not CDR), one line each naming the file and topic.
  virtual std::vector<std::string> warnings() const { return {}; }
  /// Reads every message the file holds (MCAP: decompresses every chunk and checks its CRC;
  /// sqlite3: every row, decompressed), whatever the topic filter, and tells `sink` about each
  /// one. Damage is reported, not thrown; one message (MCAP: one chunk) is in memory at a time.
  /// Independent of next(). Never writes to the file.
  virtual void verify(VerifySink& sink) = 0;
};

}  // namespace mcvio::bag
