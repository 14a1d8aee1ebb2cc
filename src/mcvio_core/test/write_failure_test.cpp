#include "mcvio/core/write_failure.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>

#include "input_error_message.hpp"

namespace mcvio {
namespace {

namespace fs = std::filesystem;
using test::errorOf;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("mcvio_write_failure_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(WriteFailure, AMissingFolderIsNamed) {
  const fs::path dir = scratch("missing");
  EXPECT_EQ(cannotWriteReason(dir / "nope" / "a.csv", ENOENT), "its folder " + (dir / "nope").string() + " does not exist");
}

TEST(WriteFailure, AFolderInTheWayIsNamed) {
  const fs::path dir = scratch("folder");
  fs::create_directories(dir / "a.csv");
  EXPECT_EQ(cannotWriteReason(dir / "a.csv", EISDIR), "it is a folder");
}

TEST(WriteFailure, AFileWhereTheFolderShouldBeIsNamed) {
  const fs::path dir = scratch("file_parent");
  std::ofstream(dir / "plain") << "x";
  EXPECT_EQ(cannotWriteReason(dir / "plain" / "a.csv", ENOTDIR), (dir / "plain").string() + " is not a folder");
}

TEST(WriteFailure, OtherwiseTheSystemsReasonIsGiven) {
  const fs::path dir = scratch("errno");
  EXPECT_EQ(cannotWriteReason(dir / "a.csv", ENOSPC), "No space left on device");
  EXPECT_EQ(cannotWriteReason(dir / "a.csv", 0), "the write failed");
}

TEST(WriteFailure, ThrowCannotWriteNamesThePathWhatAndWhy) {
  const fs::path dir = scratch("throw");
  const std::string message = errorOf([&] { throwCannotWrite(dir / "x" / "t.tum", ENOENT, "the trajectory"); });
  EXPECT_EQ(message, (dir / "x" / "t.tum").string() + ": cannot write the trajectory (its folder " + (dir / "x").string() +
                         " does not exist)");
}

}  // namespace
}  // namespace mcvio
