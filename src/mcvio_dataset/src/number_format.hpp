#pragma once
// Number-to-text helpers shared by the writers (internal to mcvio_dataset).
#include <charconv>
#include <cstdint>
#include <string>

namespace mcvio::dataset::detail {

/// Appends the shortest decimal text that reads back to exactly `value` (round-trip safe).
inline void appendDouble(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

inline void appendInt(std::string& out, std::int64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

inline std::string formatDouble(double value) {
  std::string s;
  appendDouble(s, value);
  return s;
}

}  // namespace mcvio::dataset::detail
