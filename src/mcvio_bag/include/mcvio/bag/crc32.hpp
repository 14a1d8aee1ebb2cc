#pragma once
#include <cstddef>
#include <cstdint>

namespace mcvio::bag {

/// CRC-32 (ISO-HDLC, the polynomial MCAP specifies), backed by zlib's table-driven code.
class Crc32 {
 public:
  /// Continues `crc` over the bytes; start with 0.
  static std::uint32_t update(std::uint32_t crc, const void* data, std::size_t size);
  /// CRC of A||B from crc(A), crc(B) and len(B), without touching the bytes again.
  static std::uint32_t combine(std::uint32_t crc_a, std::uint32_t crc_b, std::uint64_t len_b);
};

}  // namespace mcvio::bag
