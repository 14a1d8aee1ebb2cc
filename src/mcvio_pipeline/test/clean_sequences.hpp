#pragma once
#include <string>
#include <vector>

#include "mcvio/dataset/ground_truth_state.hpp"
#include "mcvio/pipeline/offline_run.hpp"
#include "mcvio/sim/simulator.hpp"
#include "mcvio/sim/simulator_options.hpp"

// The clean (conflict-free) sequences of the accuracy tests and the benchmark.
namespace mcvio::pipeline::sequences {

/// The real V1_01 excerpt under MCVIO_SHARED_DIR, or "" when it is absent.
std::string realExcerptDir();

/// Synthetic office, scenario `none`, `seconds` long.
sim::SimulatorOptions renderedNone(double seconds, std::uint64_t seed);

/// Semi-real: rendered along the first `seconds` of the real V1_01 ground truth, keeping its real
/// IMU and calibration. Writes the cut ground-truth and IMU CSV files into `work_dir`.
sim::SimulatorOptions semiRealV101(const std::string& excerpt_dir, const std::string& work_dir, double seconds);

/// runOffline() input that renders each stereo pair when the run asks for it (no files).
OfflineInput renderedInput(const sim::Simulator& simulator);

}  // namespace mcvio::pipeline::sequences
