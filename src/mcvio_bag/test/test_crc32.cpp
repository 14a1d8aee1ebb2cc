#include <gtest/gtest.h>
#include <zlib.h>

#include <random>
#include <vector>

#include "mcvio/bag/crc32.hpp"

namespace mcvio::bag {
namespace {

// The accelerated CRC must equal zlib's reference for every length, offset and chaining.
TEST(Crc32, MatchesZlibForAllLengthsAndSplits) {
  std::mt19937 rng(7);
  std::vector<std::uint8_t> buf(300000);
  for (auto& b : buf) b = static_cast<std::uint8_t>(rng());
  for (std::size_t len :
       {0, 1, 15, 16, 63, 64, 255, 256, 257, 300, 1023, 1024, 4099, 65536, 299990}) {
    for (std::size_t off : {0, 1, 7}) {
      const auto ref =
          static_cast<std::uint32_t>(crc32(0, buf.data() + off, static_cast<uInt>(len)));
      EXPECT_EQ(Crc32::update(0, buf.data() + off, len), ref) << len << " " << off;
      const std::size_t half = len / 3;
      const std::uint32_t a = Crc32::update(0, buf.data() + off, half);
      EXPECT_EQ(Crc32::update(a, buf.data() + off + half, len - half), ref) << len;
      const std::uint32_t b = Crc32::update(0, buf.data() + off + half, len - half);
      EXPECT_EQ(Crc32::combine(a, b, len - half), ref) << len;
    }
  }
  // The check value of CRC-32/ISO-HDLC.
  const char* nine = "123456789";
  EXPECT_EQ(Crc32::update(0, nine, 9), 0xCBF43926u);
}

}  // namespace
}  // namespace mcvio::bag
