#pragma once
#include <cstdint>
#include <filesystem>

namespace mcvio::bag {

/// What McapRepairer did to one file.
struct McapRepairReport {
  bool was_complete = false;        ///< The file was intact; nothing changed.
  std::uint64_t kept_bytes = 0;     ///< Data section bytes kept.
  std::uint64_t dropped_bytes = 0;  ///< Trailing bytes cut (partial records, old summary).
  std::uint64_t chunks = 0;
  std::uint64_t messages = 0;
};

/// Finishes an MCAP file a killed writer left behind: keeps every complete, CRC-clean record
/// (every completed chunk), cuts what follows, writes the missing message indexes of the last
/// chunk, then Data End, summary and footer. The file is changed in place.
class McapRepairer {
 public:
  static McapRepairReport repair(const std::filesystem::path& path);
};

}  // namespace mcvio::bag
