// What the component tests share: where the real excerpt is, and a DDS domain of their own.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "mcvio/dds/participant.hpp"

namespace mcvio::components::test {

/// $MCVIO_SHARED_DIR/data/euroc_V1_01_excerpt, or "" when it is absent (tests then skip).
inline std::string excerptDir() {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  const std::string dir = std::string(shared ? shared : "") + "/data/euroc_V1_01_excerpt";
  return std::filesystem::exists(dir + "/mav0") ? dir : "";
}

/// A test domain per process and per salt: parallel test runs must not hear each other.
inline mcvio::dds::ParticipantOptions testParticipantOptions(int salt) {
  mcvio::dds::ParticipantOptions po;
  po.domain_id = 100 + static_cast<int>((getpid() + salt) % 100);
  return po;
}

}  // namespace mcvio::components::test
