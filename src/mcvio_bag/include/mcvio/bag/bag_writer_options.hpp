#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include "mcvio/bag/compression.hpp"
#include "mcvio/core/time.hpp"

namespace mcvio::bag {

/// How BagWriter records. YAML keys (all optional) are given with each field.
struct BagWriterOptions {
  /// `storage`: "mcap" (default) or "sqlite3".
  std::string storage = "mcap";
  /// `compression`: "zstd" (default), "lz4" or "none". MCAP: chunk compression. sqlite3:
  /// per-message compression (rosbag2 "message" mode; only zstd is readable by rosbag2).
  Compression compression = Compression::Zstd;
  /// `compression_level`: zstd level (default 1: fast enough for camera streams) / lz4 level.
  int compression_level = 1;
  /// `chunk_size`: bytes of messages per MCAP chunk or sqlite3 transaction (default 1 MiB).
  /// This is what a killed recorder can lose at most.
  std::uint64_t chunk_size = 1024 * 1024;
  /// `max_bagfile_size`: split to a new file after this many bytes; 0 = never (default).
  std::uint64_t max_bagfile_size = 0;
  /// `max_bagfile_duration` (seconds in YAML): split after this much log time; 0 = never.
  Timestamp max_bagfile_duration = 0;
  /// `fsync`: fsync each chunk/transaction, so data also survives power loss (default false:
  /// data survives a killed process, which only needs the kernel to have it).
  bool fsync = false;
  /// `crc`: MCAP chunk, data and summary CRC-32s (default true). zlib's CRC runs at about
  /// 1 GB/s, the largest cost of uncompressed recording; false writes 0 ("not computed").
  bool crc = true;
  /// `ros_distro`: written to metadata.yaml and the sqlite3 schema table (default empty).
  std::string ros_distro;
  /// `custom_data`: string map copied to metadata.yaml.
  std::map<std::string, std::string> custom_data;

  /// Throws std::invalid_argument naming the offending field.
  void validate() const;
  /// Parses the keys above from YAML text; InputError naming `source` and the key.
  static BagWriterOptions fromYaml(const std::string& yaml, const std::string& source);
  static BagWriterOptions fromYamlFile(const std::filesystem::path& path);
};

}  // namespace mcvio::bag
