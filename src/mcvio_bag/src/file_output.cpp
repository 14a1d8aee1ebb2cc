#include "file_output.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "mcvio/bag/crc32.hpp"

namespace mcvio::bag::detail {

namespace {
constexpr std::size_t kBufferSize = 256 * 1024;

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& p) {
  throw std::system_error(errno, std::generic_category(), what + " " + p.string());
}
}  // namespace

FileOutput::FileOutput(const std::filesystem::path& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd_ < 0) fail("cannot create", path);
  buffer_.reserve(kBufferSize);
}

FileOutput::FileOutput(const std::filesystem::path& path, std::uint64_t offset,
                       std::uint32_t crc_so_far)
    : path_(path), position_(offset), crc_(crc_so_far) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd_ < 0) fail("cannot open", path);
  if (::ftruncate(fd_, static_cast<off_t>(offset)) != 0) fail("cannot truncate", path);
  if (::lseek(fd_, static_cast<off_t>(offset), SEEK_SET) < 0) fail("cannot seek in", path);
  buffer_.reserve(kBufferSize);
}

FileOutput::~FileOutput() {
  try {
    close();
  } catch (...) {
    // Destructors must not throw; close() was the caller's chance to see the error.
  }
}

void FileOutput::write(const void* data, std::size_t size) {
  if (crc_enabled_) crc_ = Crc32::update(crc_, data, size);
  const auto* p = static_cast<const std::uint8_t*>(data);
  if (buffer_.size() + size <= kBufferSize) {
    buffer_.insert(buffer_.end(), p, p + size);
  } else {
    flush();
    if (size < kBufferSize) {
      buffer_.insert(buffer_.end(), p, p + size);
    } else {
      writeAll(p, size);
    }
  }
  position_ += size;
}

void FileOutput::writeWithCrc(const void* data, std::size_t size, std::uint32_t crc_of_data) {
  const bool was = crc_enabled_;
  crc_enabled_ = false;
  write(data, size);
  crc_enabled_ = was;
  if (crc_enabled_) crc_ = Crc32::combine(crc_, crc_of_data, size);
}

void FileOutput::flush() {
  if (!buffer_.empty()) {
    writeAll(buffer_.data(), buffer_.size());
    buffer_.clear();
  }
}

void FileOutput::sync() {
  flush();
  if (fd_ >= 0 && ::fsync(fd_) != 0) fail("cannot fsync", path_);
}

void FileOutput::close() {
  if (fd_ < 0) return;
  flush();
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail("cannot close", path_);
}

void FileOutput::writeAll(const std::uint8_t* p, std::size_t n) {
  if (fd_ < 0) throw std::runtime_error("write to closed file " + path_.string());
  while (n > 0) {
    const ssize_t w = ::write(fd_, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      fail("cannot write", path_);
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
}

}  // namespace mcvio::bag::detail
