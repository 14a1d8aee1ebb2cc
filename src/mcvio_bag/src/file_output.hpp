#pragma once
// Buffered, append-only file output with a running CRC-32 (internal to mcvio_bag).
#include <cstdint>
#include <filesystem>
#include <vector>

namespace mcvio::bag::detail {

/// Sequential writer over a POSIX file descriptor. Small writes are gathered in a buffer;
/// large ones go straight to write(2). flush() hands everything to the kernel, so a process
/// killed afterwards loses nothing that was flushed.
class FileOutput {
 public:
  /// Creates `path`; fails if it exists (a bag never overwrites data).
  explicit FileOutput(const std::filesystem::path& path);
  /// Opens an existing file, cuts it at `offset` and appends from there; `crc_so_far` is the
  /// CRC of the kept bytes.
  FileOutput(const std::filesystem::path& path, std::uint64_t offset, std::uint32_t crc_so_far);
  ~FileOutput();
  FileOutput(const FileOutput&) = delete;
  FileOutput& operator=(const FileOutput&) = delete;

  void write(const void* data, std::size_t size);
  /// Like write() when the CRC of the bytes is already known (saves a pass over them).
  void writeWithCrc(const void* data, std::size_t size, std::uint32_t crc_of_data);
  void flush();
  void sync();
  void close();
  std::uint64_t position() const { return position_; }
  std::uint32_t crc() const { return crc_; }
  void resetCrc() { crc_ = 0; }
  void setCrcEnabled(bool on) { crc_enabled_ = on; }
  const std::filesystem::path& path() const { return path_; }

 private:
  void writeAll(const std::uint8_t* p, std::size_t n);
  std::filesystem::path path_;
  int fd_ = -1;
  std::vector<std::uint8_t> buffer_;
  std::uint64_t position_ = 0;
  std::uint32_t crc_ = 0;
  bool crc_enabled_ = true;
};

}  // namespace mcvio::bag::detail
