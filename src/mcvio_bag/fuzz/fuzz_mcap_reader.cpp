// libFuzzer target: any bytes given to McapReader (strict and recover) must end in messages or
// an InputError, never a crash, hang or sanitizer report.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mcvio/bag/mcap_reader.hpp"
#include "mcvio/core/input_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  for (auto mode : {mcvio::bag::McapReadMode::Strict, mcvio::bag::McapReadMode::Recover}) {
    try {
      mcvio::bag::McapReader r(std::vector<std::uint8_t>(data, data + size), "fuzz.mcap", mode);
      mcvio::bag::BagMessage m;
      while (r.next(m)) {
      }
      (void)r.statistics();
    } catch (const mcvio::InputError&) {
    }
  }
  return 0;
}
