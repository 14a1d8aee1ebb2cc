#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "mcvio/bag/bag_metadata.hpp"

namespace mcvio::bag {

/// Formats a bag's metadata like `ros2 bag info`: files, size, storage, duration, start, end,
/// message count and one line per topic with type, count and serialization format.
/// Times are printed in UTC.
std::string formatBagInfo(const BagMetadata& metadata, std::uint64_t bag_size_bytes);

/// Reads `<bag>/metadata.yaml`, sums the storage files' sizes and formats them
/// (`mcvio bag info`). InputError for a missing or malformed metadata.yaml.
std::string bagInfo(const std::filesystem::path& bag_dir);

}  // namespace mcvio::bag
