// libFuzzer target: any bytes given to McapReader (strict and recover) must end in messages or
// an InputError, never a crash, hang or sanitizer report; verify() reports, never throws.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mcvio/bag/mcap_reader.hpp"
#include "ignoring_verify_sink.hpp"
#include "mcvio/core/input_error.hpp"


extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  for (auto mode : {mcvio::bag::McapReadMode::Strict, mcvio::bag::McapReadMode::Recover}) {
    try {
      mcvio::bag::McapReader r(std::vector<std::uint8_t>(data, data + size), "fuzz.mcap", mode);
      mcvio::bag::BagMessage m;
      while (r.next(m)) {
      }
      (void)r.statistics();
      IgnoringVerifySink sink;
      r.verify(sink);
    } catch (const mcvio::InputError&) {
    }
  }
  return 0;
}
