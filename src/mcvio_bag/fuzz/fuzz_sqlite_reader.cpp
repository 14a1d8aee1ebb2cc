// libFuzzer target: any bytes as a .db3 file given to SqliteReader (plain and zstd-message
// compressed) must end in messages or an InputError, never a crash; verify() reports, never
// throws.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "mcvio/bag/sqlite_reader.hpp"
#include "ignoring_verify_sink.hpp"
#include "mcvio/core/input_error.hpp"


extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("mcvio_fuzz_" + std::to_string(getpid()) + ".db3");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  for (auto c : {mcvio::bag::Compression::None, mcvio::bag::Compression::Zstd}) {
    try {
      mcvio::bag::SqliteReader r(path, c);
      mcvio::bag::BagMessage m;
      int n = 0;
      while (r.next(m) && ++n < 10000) {
      }
      (void)r.statistics();
      IgnoringVerifySink sink;
      r.verify(sink);
    } catch (const mcvio::InputError&) {
    }
  }
  std::filesystem::remove(path);
  return 0;
}
