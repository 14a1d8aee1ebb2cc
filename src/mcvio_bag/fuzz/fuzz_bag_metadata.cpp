// libFuzzer target: metadata.yaml text must parse or end in an InputError, nothing else.
#include <cstddef>
#include <cstdint>
#include <string>

#include "mcvio/bag/bag_metadata.hpp"
#include "mcvio/core/input_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto m = mcvio::bag::bagMetadataFromYaml(
        std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
    (void)mcvio::bag::bagMetadataToYaml(m);
  } catch (const mcvio::InputError&) {
  }
  return 0;
}
