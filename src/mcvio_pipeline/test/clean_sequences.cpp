#include "clean_sequences.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "mcvio/core/input_error.hpp"

namespace mcvio::pipeline::sequences {
namespace {

// Copies the header and the rows of a EuRoC CSV whose timestamp lies within `seconds` of the first.
void cutCsv(const std::string& from, const std::string& to, double seconds) {
  std::ifstream in(from);
  if (!in) throw InputError("cannot read " + from);
  std::ofstream out(to);
  if (!out) throw InputError("cannot write " + to);
  std::string line;
  long long t0 = -1;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      out << line << '\n';
      continue;
    }
    const long long t = std::stoll(line.substr(0, line.find(',')));
    if (t0 < 0) t0 = t;
    if (static_cast<double>(t - t0) * 1e-9 > seconds + 1e-6) break;
    out << line << '\n';
  }
}

}  // namespace

std::string realExcerptDir() {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  if (!shared) return "";
  const std::string dir = std::string(shared) + "/data/euroc_V1_01_excerpt";
  return std::filesystem::exists(dir + "/mav0/state_groundtruth_estimate0/data.csv") ? dir : "";
}

sim::SimulatorOptions renderedNone(double seconds, std::uint64_t seed) {
  sim::SimulatorOptions o;
  o.seed = seed;
  o.duration_s = seconds;
  o.overwrite = true;
  o.scenario.kind = sim::ScenarioKind::kNone;
  o.scenario.onset_s = 0;  // no conflict: its timing must only fit in the sequence
  o.scenario.duration_s = 0;
  return o;
}

sim::SimulatorOptions semiRealV101(const std::string& excerpt_dir, const std::string& work_dir, double seconds) {
  std::filesystem::create_directories(work_dir);
  sim::SimulatorOptions o;
  o.overwrite = true;
  o.calibration_dir = excerpt_dir;
  o.groundtruth_csv = work_dir + "/groundtruth.csv";
  o.imu_csv = work_dir + "/imu.csv";
  o.scenario.kind = sim::ScenarioKind::kNone;
  o.scenario.onset_s = 0;
  o.scenario.duration_s = 0;
  cutCsv(excerpt_dir + "/mav0/state_groundtruth_estimate0/data.csv", o.groundtruth_csv, seconds);
  cutCsv(excerpt_dir + "/mav0/imu0/data.csv", o.imu_csv, seconds);
  return o;
}

OfflineInput renderedInput(const sim::Simulator& simulator) {
  OfflineInput in;
  in.calibration = simulator.calibration();
  in.imu = simulator.imu();
  in.frame_times = simulator.frameTimes();
  in.images = [&simulator](std::size_t i) {
    auto r = simulator.renderFrame(i);
    return std::make_pair(r.cam0, r.cam1);
  };
  return in;
}

}  // namespace mcvio::pipeline::sequences
