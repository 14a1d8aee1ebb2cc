#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mcvio/bag/bag_metadata.hpp"

namespace mcvio::bag {

/// Formats a bag's metadata like `ros2 bag info`: files, size, storage, duration, start, end,
/// message count and one line per topic with type, count and serialization format.
/// Times are printed in UTC.
std::string formatBagInfo(const BagMetadata& metadata, std::uint64_t bag_size_bytes);

/// Reads `<bag>/metadata.yaml`, sums the storage files' sizes and formats them
/// (`mcvio bag info`). InputError for a missing or malformed metadata.yaml. Each storage file
/// is opened (MCAP: magic, footer, summary; sqlite3: its tables) and compared with
/// metadata.yaml; `warnings` (optional) receives one line per disagreement or unreadable file,
/// naming the file and topic or field. A single .mcap or .db3 file is described from its own
/// summary.
std::string bagInfo(const std::filesystem::path& bag,
                    std::vector<std::string>* warnings = nullptr);

}  // namespace mcvio::bag
