#include "commands/image_level_benchmark.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>

#include "mcvio/core/input_error.hpp"
#include "mcvio/evaluation/detector_log.hpp"
#include "mcvio/evaluation/trajectory_io.hpp"
#include "mcvio/pipeline/offline_run.hpp"
#include "mcvio/sim/image_injector.hpp"
#include "mcvio/sim/simulator.hpp"

namespace mcvio::cli {

namespace {

namespace fs = std::filesystem;
namespace ev = mcvio::evaluation;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// mav0/ of a EuRoC folder given as the folder or as mav0 itself.
fs::path mav0Of(const std::string& dir) {
  const fs::path p(dir);
  return fs::is_directory(p / "mav0") ? p / "mav0" : p;
}

/// Byte-for-byte equal files (both readable).
bool sameContents(const fs::path& a, const fs::path& b) {
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  if (!fa || !fb) return false;
  return std::equal(std::istreambuf_iterator<char>(fa), std::istreambuf_iterator<char>(),
                    std::istreambuf_iterator<char>(fb), std::istreambuf_iterator<char>());
}

/// One mode of `mcvio run` over a rendered folder, read back as a benchmark run.
ev::BenchmarkModeRun runMode(const std::string& dataset, const std::string& out, const std::string& mode,
                             const std::string& config) {
  pipeline::OfflineRunOptions ro;
  ro.dataset_dir = dataset;
  ro.output_dir = out;
  ro.mode = mode;
  ro.config_file = config;
  ro.progress = false;
  ev::BenchmarkModeRun run;
  run.mode = mode;
  std::mutex mutex;  // on_frame comes from the estimator thread
  ro.on_frame = [&](std::size_t, const pipeline::VioFrameResult& r) {
    if (!r.estimated || !r.estimate.frame_accepted || r.estimate.status != estimator::EstimatorStatus::kTracking) return;
    std::lock_guard<std::mutex> lock(mutex);
    run.cpu_ms.push_back(r.estimate.timings.cpu_total_ms);
    run.conflict_ms.push_back(r.estimate.timings.conflict_ms);
  };
  const auto t0 = Clock::now();
  const pipeline::OfflineRunSummary summary = pipeline::runOffline(ro);
  run.wall_s = secondsSince(t0);
  run.frames = summary.frames;
  run.resets = int(summary.resets);
  const fs::path o(out);
  run.estimate = ev::loadTum((o / "trajectory.tum").string());
  if (auto online = ev::loadOnlineTrajectory(out)) run.estimate_online = std::move(*online);
  run.detector = ev::DetectorLog::load((o / "conflict.csv").string()).records();
  run.secondary = ev::loadTum((o / "secondary.tum").string(), ev::EmptyTum::kEmptyTrajectory);
  return run;
}

}  // namespace

double ImageLevelBenchmark::cleanFloor(const std::string& base_dir, const ev::BenchmarkSequence& sequence) const {
  ev::BenchmarkSequence clean = sequence;
  clean.scenario = "none";
  clean.name = sequence.name + "_base";
  clean.conflict_duration_s = 0;
  const fs::path out = fs::path(options_.work_dir) / "runs" / clean.name / "reference";
  std::vector<ev::BenchmarkModeRun> runs{runMode(base_dir, out.string(), "reference", options_.pipeline_config)};
  const ev::Trajectory ground_truth = ev::loadEurocGroundTruth(base_dir);
  ev::BenchmarkOptions reference_only = options_.suite;
  reference_only.modes = {"reference"};
  const auto sr = ev::BenchmarkSuite::evaluateSequence(clean, ground_truth, ev::ConflictLabelTimeline::load(base_dir), runs,
                                                       reference_only);
  return sr.runs.empty() ? ev::BenchmarkRun::kNaN : sr.runs.front().ate_posyaw_m;
}

ImageLevelBenchmark::ImageLevelBenchmark(Options options) : options_(std::move(options)) {
  options_.suite.validate();
  if (options_.work_dir.empty()) throw std::invalid_argument("work_dir: empty");
  for (const auto& dir : options_.real_dirs)
    if (!fs::is_regular_file(mav0Of(dir) / "state_groundtruth_estimate0/data.csv"))
      throw InputError(dir + ": no mav0/state_groundtruth_estimate0/data.csv (a real sequence needs its ground truth)");
  if (!options_.rig_calibration_dir.empty() && !fs::is_directory(options_.rig_calibration_dir))
    throw InputError(options_.rig_calibration_dir + ": no such folder (the rig to render with: cam0/, cam1/, imu0/ sensor.yaml)");
  if (!options_.semi_real_dir.empty()) {
    const fs::path m = mav0Of(options_.semi_real_dir);
    for (const char* f : {"state_groundtruth_estimate0/data.csv", "imu0/data.csv"})
      if (!fs::is_regular_file(m / f)) throw InputError(options_.semi_real_dir + ": no mav0/" + f + " for the semi-real sequence");
  }
}

ev::BenchmarkResult ImageLevelBenchmark::run(const ev::BenchmarkSuite::Progress& progress) const {
  const auto t0 = Clock::now();
  const ev::BenchmarkOptions& so = options_.suite;
  std::vector<ev::BenchmarkSequence> plan = ev::BenchmarkSuite(so).plan();
  if (!options_.semi_real_dir.empty()) {
    ev::BenchmarkSequence s;
    s.scenario = "injected_overlay";
    s.name = "overlay_semi_real";
    s.seed = so.seeds.front();
    s.onset_s = options_.overlay_onset_s;
    s.conflict_duration_s = options_.overlay_duration_s;
    plan.push_back(s);
  }
  for (const auto& dir : options_.real_dirs) {
    ev::BenchmarkSequence s;
    s.scenario = "none";
    fs::path p = fs::absolute(fs::path(dir)).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();  // "dir/" names its last component
    if (p.filename() == "mav0") p = p.parent_path();
    s.name = "real_" + p.filename().string();
    s.seed = 0;
    plan.push_back(s);
  }
  const std::size_t real_begin = plan.size() - options_.real_dirs.size();
  // Plus the reference run on the overlay's base sequence (the clean floor).
  const std::size_t total = plan.size() * so.modes.size() + (options_.semi_real_dir.empty() ? 0 : 1);
  std::size_t done = 0;
  auto report = [&](const std::string& line) {
    ++done;
    if (progress) progress(done, total, line);
  };

  ev::BenchmarkResult result;
  result.level = "images";
  result.render_rig = options_.rig_calibration_dir;
  result.texture_filter = sim::toString(options_.texture_filter);
  result.options = so;
  for (std::size_t index = 0; index < plan.size(); ++index) {
    auto& sequence = plan[index];
    const bool real = index >= real_begin;
    const fs::path data = real ? fs::path(options_.real_dirs[index - real_begin]) : fs::path(options_.work_dir) / "data" / sequence.name;
    const auto t_render = Clock::now();
    sim::SimulatorOptions sim;
    sim.output_dir = data.string();
    sim.overwrite = true;
    sim.seed = sequence.seed;
    sim.texture_filter = options_.texture_filter;
    if (real) {
      // Recorded: nothing to render.
    } else if (sequence.scenario == "injected_overlay") {
      // Render the office along the recorded ground truth with the real IMU, then inject the overlay.
      const fs::path m = mav0Of(options_.semi_real_dir);
      sim.groundtruth_csv = (m / "state_groundtruth_estimate0/data.csv").string();
      sim.imu_csv = (m / "imu0/data.csv").string();
      sim.calibration_dir = options_.semi_real_dir;
      sim.output_dir = (data.string() + "_base");
      sim::Simulator(sim).writeDataset();
      sim::InjectOptions inject;
      inject.input_dir = sim.output_dir;
      inject.output_dir = data.string();
      inject.overwrite = true;
      inject.onset_s = sequence.onset_s;
      inject.duration_s = sequence.conflict_duration_s;
      inject.seed = sequence.seed;
      sim::runInjection(inject);
    } else {
      sim.duration_s = sequence.duration_s;
      sim.calibration_dir = options_.rig_calibration_dir;
      sim.scenario.kind = sim::scenarioKindFromString(sequence.scenario);
      sim.scenario.onset_s = sequence.onset_s;
      sim.scenario.duration_s = sequence.conflict_duration_s;
      sim.scenario.travel_m = sequence.travel_m;
      sim::Simulator(sim).writeDataset();
    }
    const double render_s = secondsSince(t_render);

    const ev::Trajectory ground_truth = ev::loadEurocGroundTruth(data.string());
    if (sequence.scenario == "injected_overlay" || real) sequence.duration_s = ground_truth.durationSeconds();
    std::vector<ev::BenchmarkModeRun> runs;
    for (const auto& mode : so.modes) {
      const fs::path out = fs::path(options_.work_dir) / "runs" / sequence.name / mode;
      runs.push_back(runMode(data.string(), out.string(), mode, options_.pipeline_config));
      const auto& r = runs.back();
      char buf[160];
      std::snprintf(buf, sizeof buf, ": %zu/%zu frames tracked, %.1f s", r.estimate.size(), r.frames, r.wall_s);
      report(sequence.name + " " + mode + buf + (real ? std::string() : " (rendered in " + std::to_string(int(render_s)) + " s)"));
    }
    ev::ConflictLabelTimeline labels;
    if (!real || fs::is_regular_file(mav0Of(data.string()) / "conflict_labels.csv")) {
      labels = ev::ConflictLabelTimeline::load(data.string());
    } else {
      // A recorded sequence without labels: every estimated frame is conflict-free.
      std::vector<Timestamp> times;
      for (const auto& r : runs)
        for (const auto& p : r.estimate.poses()) times.push_back(p.t);
      std::sort(times.begin(), times.end());
      times.erase(std::unique(times.begin(), times.end()), times.end());
      std::vector<dataset::ConflictLabel> clean;
      for (Timestamp t : times) clean.push_back({t, false, "none", 0.0});
      labels = ev::ConflictLabelTimeline(std::move(clean), data.string() + " (no labels: all frames clean)");
    }
    ev::BenchmarkSequenceResult sr = ev::BenchmarkSuite::evaluateSequence(sequence, ground_truth, labels, runs, so);
    sr.simulate_s = render_s;
    if (sequence.scenario == "injected_overlay") {
      sr.clean_floor_ate_m = cleanFloor(data.string() + "_base", sequence);
      char buf[96];
      std::snprintf(buf, sizeof buf, "_base reference (clean floor): ATE pos+yaw %.3f m", sr.clean_floor_ate_m);
      report(sequence.name + buf);
    }
    result.sequences.push_back(std::move(sr));
  }
  // A scenario rendered along the clean office's trajectory with its IMU (a pedestrian, a carried
  // laptop, a slow object in an otherwise static world) has that office as its clean floor.
  for (std::size_t i = 0; i < real_begin; ++i) {
    auto& sr = result.sequences[i];
    if (!sr.sequence.hasConflict() || sr.sequence.scenario == "injected_overlay") continue;
    for (std::size_t c = 0; c < real_begin; ++c) {
      const auto& clean = result.sequences[c];
      const ev::BenchmarkRun* ref = clean.find("reference");
      if (clean.sequence.scenario != "none" || clean.sequence.seed != sr.sequence.seed || ref == nullptr) continue;
      const fs::path a = mav0Of((fs::path(options_.work_dir) / "data" / sr.sequence.name).string());
      const fs::path b = mav0Of((fs::path(options_.work_dir) / "data" / clean.sequence.name).string());
      if (sameContents(a / "state_groundtruth_estimate0/data.csv", b / "state_groundtruth_estimate0/data.csv") &&
          sameContents(a / "imu0/data.csv", b / "imu0/data.csv"))
        sr.clean_floor_ate_m = ref->ate_posyaw_m;
    }
  }
  ev::BenchmarkSuite::applyTargets(result);
  result.wall_s = secondsSince(t0);
  return result;
}

}  // namespace mcvio::cli
