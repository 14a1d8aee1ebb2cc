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
};

}  // namespace mcvio::bag
