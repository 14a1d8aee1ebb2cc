#include "mcvio/bag/crc32.hpp"

#include <zlib.h>

#include <algorithm>
#include <limits>

namespace mcvio::bag {

std::uint32_t Crc32::update(std::uint32_t crc, const void* data, std::size_t size) {
  const auto* p = static_cast<const Bytef*>(data);
  uLong c = crc;
  // zlib takes uInt lengths: feed large buffers in pieces.
  while (size > 0) {
    const std::size_t n = std::min<std::size_t>(size, std::numeric_limits<uInt>::max());
    c = ::crc32(c, p, static_cast<uInt>(n));
    p += n;
    size -= n;
  }
  return static_cast<std::uint32_t>(c);
}

std::uint32_t Crc32::combine(std::uint32_t crc_a, std::uint32_t crc_b, std::uint64_t len_b) {
  return static_cast<std::uint32_t>(::crc32_combine(crc_a, crc_b, static_cast<z_off_t>(len_b)));
}

}  // namespace mcvio::bag
