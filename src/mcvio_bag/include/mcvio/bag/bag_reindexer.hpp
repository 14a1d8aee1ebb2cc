#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "mcvio/bag/bag_metadata.hpp"

namespace mcvio::bag {

/// Rebuilds a bag after a crash (`mcvio bag reindex`): finishes unfinished MCAP files
/// (McapRepairer), folds sqlite3 write-ahead logs into their .db3 files, and rewrites
/// metadata.yaml from what the storage files really hold.
class BagReindexer {
 public:
  /// Returns the new metadata. InputError when the directory holds no storage files, mixes
  /// .mcap and .db3, or no file can be read at all. A file that cannot be read at all (e.g. not
  /// MCAP) next to readable ones is left in place, out of the new metadata.yaml, and named in
  /// `damage`.
  /// `log` (optional) receives one line per file describing what was done, plus where an
  /// original was kept and what a killed writer's unfinished tail lost. `damage` (optional)
  /// receives one line per damaged record that was dropped (file, byte offset, size, messages
  /// lost when known): data was lost that had been written completely. Files the old
  /// metadata.yaml listed that are gone are named in `log`. A damaged sqlite3 file (failed
  /// quick_check) is an InputError: reindex does not salvage sqlite3 pages. For sqlite3 the
  /// message compression comes from the messages (a warning in `log` when the old metadata.yaml
  /// said otherwise).
  static BagMetadata reindex(const std::filesystem::path& bag_dir,
                             std::vector<std::string>* log = nullptr,
                             std::vector<std::string>* damage = nullptr);
};

}  // namespace mcvio::bag
