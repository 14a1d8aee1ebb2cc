// Times a whole simulated EuRoC sequence written to disk (default: 60 s, 20 Hz stereo = 2400
// images) and prints the figures. Usage: mcvio_sim_sequence_timing [scenario] [output_dir]
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "mcvio/core/input_error.hpp"
#include "mcvio/sim/simulator.hpp"

int main(int argc, char** argv) {
  try {
    mcvio::sim::SimulatorOptions o;
    o.scenario.kind = mcvio::sim::scenarioKindFromString(argc > 1 ? argv[1] : "none");
    o.output_dir = argc > 2 ? argv[2] : (std::filesystem::temp_directory_path() / "mcvio_sim_timing").string();
    o.overwrite = true;
    const auto t0 = std::chrono::steady_clock::now();
    mcvio::sim::Simulator sim(o);
    const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const mcvio::sim::SimulationSummary s = sim.writeDataset();
    std::printf("scenario %s: %zu stereo frames (%zu images), %zu IMU samples, %zu conflict frames\n",
                mcvio::sim::toString(o.scenario.kind), s.frames, 2 * s.frames, s.imu_samples, s.conflict_frames);
    std::printf("setup (textures, world, IMU): %.2f s\n", setup);
    std::printf("rendering: %.2f s (%.1f stereo pairs/s, %.1f images/s)\n", s.render_seconds,
                s.frames / s.render_seconds, 2 * s.frames / s.render_seconds);
    std::printf("write whole data set incl. PNG encoding: %.2f s (%.1f images/s)\n", s.total_seconds,
                2 * s.frames / s.total_seconds);
    std::printf("output: %s\n", o.output_dir.c_str());
  } catch (const mcvio::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
