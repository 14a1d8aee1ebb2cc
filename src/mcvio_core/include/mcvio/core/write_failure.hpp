#pragma once
#include <filesystem>
#include <string>

namespace mcvio {

/// Why PATH could not be written, in words a user can act on: "its folder /x does not exist",
/// "it is a folder", "no permission to write in /x", else the system's reason for SAVED_ERRNO
/// (e.g. "No space left on device"). Checks the path first because errno after a failed stream
/// or image write is not always the cause.
std::string cannotWriteReason(const std::filesystem::path& path, int saved_errno);

/// Throws mcvio::InputError "PATH: cannot write WHAT (REASON)"; WHAT defaults to "it".
[[noreturn]] void throwCannotWrite(const std::filesystem::path& path, int saved_errno,
                                   const std::string& what = "it");

}  // namespace mcvio
