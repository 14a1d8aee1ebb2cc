#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mcvio::bag {

/// Compression of MCAP chunks (or, for sqlite3 storage, of each message as rosbag2's
/// "message" compression mode does). LZ4 uses the LZ4 frame format, as MCAP requires.
enum class Compression { None, Zstd, Lz4 };

/// "none"/"" -> None, "zstd" -> Zstd, "lz4" -> Lz4; throws std::invalid_argument otherwise.
Compression compressionFromString(const std::string& name);
/// The MCAP spelling: "" for None, "zstd", "lz4".
std::string mcapCompressionName(Compression c);
/// The option spelling: "none", "zstd", "lz4".
std::string toString(Compression c);

/// Compresses and decompresses byte buffers with libzstd / liblz4 (frame format).
class Codec {
 public:
  /// Appends the compressed form of [data, data+size) to `out`. `level` is a zstd level
  /// (1 = fast) or an lz4 frame compression level (0 = fast).
  static void compress(Compression c, const std::uint8_t* data, std::size_t size, int level,
                       std::vector<std::uint8_t>& out);
  /// Decompresses into `out` (resized to exactly `expected_size`). Throws std::runtime_error
  /// with the codec's reason when the input is corrupt or the size does not match; callers add
  /// the file and offset.
  static void decompress(Compression c, const std::uint8_t* data, std::size_t size,
                         std::size_t expected_size, std::vector<std::uint8_t>& out);
  /// Decompresses a self-describing frame whose content size may be unknown (sqlite3 message
  /// compression); `max_size` bounds the output so corrupt input cannot exhaust memory.
  static void decompressFrame(Compression c, const std::uint8_t* data, std::size_t size,
                              std::size_t max_size, std::vector<std::uint8_t>& out);
};

}  // namespace mcvio::bag
