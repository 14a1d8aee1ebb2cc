#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "mcvio/bag/bag_metadata.hpp"

namespace mcvio::bag {

/// Formats a bag's metadata like `ros2 bag info`: files, size, storage, duration, start, end,
/// message count and one line per topic with type, count and serialization format.
/// Times are printed in UTC.
std::string formatBagInfo(const BagMetadata& metadata, std::uint64_t bag_size_bytes);

/// What reading every message found for one topic (`mcvio bag info --verify`).
struct TopicVerification {
  std::uint64_t readable = 0;    ///< Messages read (and decompressed) intact.
  std::uint64_t unreadable = 0;  ///< Messages that cannot be read.
  /// The first unreadable one in file order: file, row id or byte offset, log time, why, and
  /// whether `mcvio bag reindex` can do anything about it.
  std::string first_unreadable;
  /// Messages metadata.yaml lists that the storage files no longer hold (counted only when a
  /// file did not open strictly: truncated, damaged or missing).
  std::uint64_t missing = 0;
};

/// What reading every message of every storage file found (BagInfoOptions::verify).
struct BagVerification {
  std::uint64_t readable = 0;
  std::uint64_t unreadable = 0;
  /// Messages metadata.yaml lists beyond those found, minus unreadable ones of unknown topic.
  std::uint64_t missing = 0;
  /// Per topic; "" collects lost messages whose topic the file no longer tells.
  std::map<std::string, TopicVerification> topics;
  /// Damage that is not a topic's messages (e.g. a bad MCAP data section CRC, an sqlite3 scan
  /// cut short with an unknown number of rows beyond).
  std::vector<std::string> problems;
  /// Storage files that could not be opened at all (their warning says why).
  std::uint64_t files_unread = 0;
  bool clean() const {
    return unreadable == 0 && missing == 0 && problems.empty() && files_unread == 0;
  }
};

struct BagInfoOptions {
  /// Also read and decompress every message of every storage file, one message (MCAP: one
  /// chunk) in memory at a time, never writing to the bag. Takes as long as reading the bag.
  bool verify = false;
  /// With verify: called every few thousand messages with the number checked so far.
  std::function<void(std::uint64_t)> progress;
};

/// Reads `<bag>/metadata.yaml`, sums the storage files' sizes and formats them
/// (`mcvio bag info`). InputError for a missing or malformed metadata.yaml. Each storage file
/// is opened (MCAP: magic, footer, summary; sqlite3: its tables, statistics and first message)
/// and compared with metadata.yaml; `warnings` (optional) receives one line per disagreement or
/// unreadable file, naming the file and topic or field, and what `mcvio bag reindex` would do
/// about it only where it repairs that problem. A single .mcap or .db3 file is described from
/// its own summary.
std::string bagInfo(const std::filesystem::path& bag,
                    std::vector<std::string>* warnings = nullptr);

/// bagInfo() with options. With `options.verify` the text ends with a "Verified:" line,
/// `warnings` gets one line per topic with unreadable messages (how many, the first one) and
/// one per problem, and `verification` (optional) the counts.
std::string bagInfo(const std::filesystem::path& bag, std::vector<std::string>* warnings,
                    const BagInfoOptions& options, BagVerification* verification = nullptr);

}  // namespace mcvio::bag
