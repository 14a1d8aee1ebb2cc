#include "mcvio/core/write_failure.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "mcvio/core/input_error.hpp"

namespace mcvio {

std::string cannotWriteReason(const std::filesystem::path& path, int saved_errno) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) return "it is a folder";
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::exists(parent, ec)) return "its folder " + parent.string() + " does not exist";
  if (!fs::is_directory(parent, ec)) return parent.string() + " is not a folder";
  if (saved_errno == EROFS) return parent.string() + " is on a read-only file system";
  if (fs::exists(path, ec) && ::access(path.c_str(), W_OK) != 0) return "no permission to write it";
  if (!fs::exists(path, ec) && ::access(parent.c_str(), W_OK) != 0)
    return "no permission to write in " + parent.string();
  if (saved_errno != 0) return std::strerror(saved_errno);
  return "the write failed";
}

void throwCannotWrite(const std::filesystem::path& path, int saved_errno, const std::string& what) {
  throw InputError(path.string() + ": cannot write " + what + " (" + cannotWriteReason(path, saved_errno) + ")");
}

}  // namespace mcvio
