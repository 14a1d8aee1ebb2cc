#pragma once
// EuRoC folder checks shared by the readers (internal to mcvio_dataset).
#include <filesystem>
#include <string>

#include "mcvio/core/input_error.hpp"

namespace mcvio::dataset::detail {

inline std::string requireDir(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec))
    throw InputError(path.string() + ": missing folder");
  return path.string();
}

inline std::string requireFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string() + (std::filesystem::is_directory(path, ec) ? ": is a folder, expected a file"
                                                                              : ": missing file"));
  }
  return path.string();
}

/// The mav0 folder of `dir`: dir/mav0, or dir itself if it holds cam0/ or imu0/; absolute.
inline std::filesystem::path resolveMav0(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path base(dir);
  if (!fs::is_directory(base, ec)) {
    if (fs::exists(base, ec))
      throw InputError(dir + ": is a file, not a EuRoC folder (a folder holding mav0/, or cam0/ and imu0/; a bag is a "
                             ".mcap/.db3 file or its folder with metadata.yaml)");
    throw InputError(dir + ": EuRoC folder does not exist");
  }
  fs::path root = base / "mav0";
  if (!fs::is_directory(root, ec)) {
    if (!fs::is_directory(base / "cam0", ec) && !fs::is_directory(base / "imu0", ec)) {
      throw InputError(dir + ": not a EuRoC folder (no mav0 folder, and no cam0/imu0 in it)");
    }
    root = base;
  }
  const fs::path absolute = fs::absolute(root, ec);
  return ec ? root : absolute.lexically_normal();
}

}  // namespace mcvio::dataset::detail
