#pragma once
#include <functional>
#include <string>
#include <vector>

#include "mcvio/evaluation/benchmark_options.hpp"
#include "mcvio/evaluation/benchmark_result.hpp"
#include "mcvio/evaluation/conflict_label_timeline.hpp"

namespace mcvio::evaluation {

/// The MC-VIO benchmark at feature level: for every planned sequence the FeatureSimulator makes
/// stereo feature tracks, IMU, ground truth and per-frame conflict labels; every resolution mode
/// runs the SlidingWindowEstimator on them; the Evaluator measures ATE, RPE and per-frame
/// detection against the truth, and each run is compared with `reference` on the same sequence
/// and checked against BenchmarkTargets.
class BenchmarkSuite {
 public:
  /// Called once per finished (sequence, mode) run, from worker threads but never concurrently:
  /// `done` of `total` runs, and a one-line summary.
  using Progress = std::function<void(std::size_t done, std::size_t total, const std::string& line)>;

  /// Throws std::invalid_argument naming a bad option.
  explicit BenchmarkSuite(BenchmarkOptions options);

  /// The sequences run() will simulate: each scenario x seed, then the duration sweep.
  std::vector<BenchmarkSequence> plan() const;

  /// Runs everything (options.jobs sequences at a time) and fills the target summary.
  BenchmarkResult run(const Progress& progress = {}) const;

  /// Simulates one sequence and runs every mode on it; `on_run` gets a one-line summary per mode.
  BenchmarkSequenceResult runSequence(const BenchmarkSequence& sequence,
                                      const std::function<void(const std::string&)>& on_run = {}) const;

  /// Measures every mode's run of one sequence against its ground truth and labels and against
  /// the `reference` run (which `runs` must hold). Used by runSequence() and by image-level runs.
  static BenchmarkSequenceResult evaluateSequence(const BenchmarkSequence& sequence, const Trajectory& ground_truth,
                                                  const ConflictLabelTimeline& labels,
                                                  const std::vector<BenchmarkModeRun>& runs,
                                                  const BenchmarkOptions& options);

  /// Fills each run's checks and result.targets from the measured values.
  static void applyTargets(BenchmarkResult& result);

  const BenchmarkOptions& options() const { return options_; }

 private:
  BenchmarkOptions options_;
};

}  // namespace mcvio::evaluation
