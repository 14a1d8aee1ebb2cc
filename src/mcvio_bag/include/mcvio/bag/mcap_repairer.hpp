#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include "mcvio/bag/mcap_reader.hpp"

namespace mcvio::bag {

/// What McapRepairer did to one file.
struct McapRepairReport {
  bool was_complete = false;        ///< The file was intact; nothing changed.
  std::uint64_t kept_bytes = 0;     ///< Data section bytes kept.
  std::uint64_t dropped_bytes = 0;  ///< Trailing bytes cut (partial records, old summary).
  std::uint64_t chunks = 0;
  std::uint64_t messages = 0;
  /// Every stretch that was dropped (damaged records, the unfinished tail); empty when only the
  /// summary was rebuilt.
  std::vector<McapDamage> damage;
  /// Where the untouched original was kept (`<file>.orig`); empty unless damage inside the file
  /// was dropped.
  std::filesystem::path original;
  /// Damaged records (not just a killed writer's unfinished tail) were dropped.
  bool damaged() const;
};

/// Finishes an MCAP file a killed writer left behind or repairs a damaged one: keeps every
/// complete, CRC-clean record (every intact chunk, also those after a damaged one), writes the
/// missing message indexes of the last chunk, then Data End, summary and footer. A file is
/// "intact" only when its summary, every chunk's CRC and its message indexes check out.
/// When at most the unfinished last record is dropped the tail is rewritten in place; when
/// damage inside the file is dropped the repaired file is written next to it, read back strictly,
/// and only then the original is renamed to `<file>.orig` (`.orig.1`, ... if taken) and the
/// repaired file takes its name.
class McapRepairer {
 public:
  static McapRepairReport repair(const std::filesystem::path& path);
};

}  // namespace mcvio::bag
