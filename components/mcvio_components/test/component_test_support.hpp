// What the component tests share: where the real excerpt is, and a DDS domain of their own.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "mcvio/dds/participant.hpp"
#include "mcvio/sim/simulator.hpp"

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

/// Renders a conflict-free simulated sequence (the office, moving) of `seconds` into `dir`.
inline void writeCleanSequence(const std::string& dir, std::uint64_t seed, double seconds) {
  mcvio::sim::SimulatorOptions so;
  so.output_dir = dir;
  so.overwrite = true;
  so.seed = seed;
  so.duration_s = seconds;
  so.scenario.kind = mcvio::sim::ScenarioKind::kNone;
  so.scenario.onset_s = seconds / 4;  // unused without a conflict, but validated against the length
  so.scenario.duration_s = seconds / 4;
  mcvio::sim::Simulator(so).writeDataset();
}

}  // namespace mcvio::components::test
