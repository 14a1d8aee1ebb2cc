#pragma once
// Little-endian serialization helpers for MCAP records (internal to mcvio_bag).
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace mcvio::bag::detail {

/// Appends little-endian fields to a byte vector.
class ByteWriter {
 public:
  explicit ByteWriter(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v) { raw(&v, 2); }
  void u32(std::uint32_t v) { raw(&v, 4); }
  void u64(std::uint64_t v) { raw(&v, 8); }
  void str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
  void raw(const void* p, std::size_t n) {
    // The host is little endian (x86-64/aarch64); CMake checks it.
    const auto* b = static_cast<const std::uint8_t*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  void stringMap(const std::map<std::string, std::string>& m) {
    const std::size_t at = out_.size();
    u32(0);
    for (const auto& [k, v] : m) {
      str(k);
      str(v);
    }
    patchU32(at, static_cast<std::uint32_t>(out_.size() - at - 4));
  }
  void patchU32(std::size_t at, std::uint32_t v) { std::memcpy(out_.data() + at, &v, 4); }
  void patchU64(std::size_t at, std::uint64_t v) { std::memcpy(out_.data() + at, &v, 8); }
  std::size_t size() const { return out_.size(); }

 private:
  std::vector<std::uint8_t>& out_;
};

/// Thrown by ByteReader when a field runs past its record; `offset` is relative to the buffer.
struct ShortRead : std::runtime_error {
  ShortRead(const std::string& what, std::uint64_t at) : std::runtime_error(what), offset(at) {}
  std::uint64_t offset;
};

/// Bounds-checked little-endian reader over a byte range.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}
  std::uint8_t u8() { return fixed<std::uint8_t>(); }
  std::uint16_t u16() { return fixed<std::uint16_t>(); }
  std::uint32_t u32() { return fixed<std::uint32_t>(); }
  std::uint64_t u64() { return fixed<std::uint64_t>(); }
  std::string str(const char* field) {
    const std::uint32_t len = u32();
    need(len, field);
    std::string s(reinterpret_cast<const char*>(p_ + pos_), len);
    pos_ += len;
    return s;
  }
  /// A uint32-length-prefixed byte range; returns a reader over it and skips it.
  ByteReader sub32(const char* field) {
    const std::uint32_t len = u32();
    need(len, field);
    ByteReader r(p_ + pos_, len);
    pos_ += len;
    return r;
  }
  std::map<std::string, std::string> stringMap(const char* field) {
    ByteReader r = sub32(field);
    std::map<std::string, std::string> m;
    while (!r.done()) {
      std::string k = r.str(field);
      m[k] = r.str(field);
    }
    return m;
  }
  const std::uint8_t* here() const { return p_ + pos_; }
  void skip(std::size_t n, const char* field) {
    need(n, field);
    pos_ += n;
  }
  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return n_ - pos_; }
  bool done() const { return pos_ >= n_; }
  void need(std::size_t n, const char* field) const {
    if (n > n_ - pos_) {
      throw ShortRead(std::string("field '") + field + "' runs past the end of its record", pos_);
    }
  }

 private:
  template <typename T>
  T fixed() {
    need(sizeof(T), "integer");
    T v;
    std::memcpy(&v, p_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  const std::uint8_t* p_;
  std::size_t n_;
  std::size_t pos_ = 0;
};

}  // namespace mcvio::bag::detail
