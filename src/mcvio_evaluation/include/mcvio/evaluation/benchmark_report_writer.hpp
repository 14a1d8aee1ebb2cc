#pragma once
#include <string>
#include <vector>

#include "mcvio/evaluation/benchmark_result.hpp"

namespace mcvio::evaluation {

/// The one report of a benchmark: JSON for scripts, Markdown tables for people, PNG figures.
///
/// Markdown: the target summary (per target and MC-VIO mode: runs passing, the worst value), a
/// table per scenario sequence and mode (ATE, RPE, reductions versus reference, detection, CPU,
/// cost, checks), the elevator ride, and ATE against the conflict duration.
class BenchmarkReportWriter {
 public:
  static std::string toJson(const BenchmarkResult& result);
  static std::string toMarkdown(const BenchmarkResult& result);

  /// Figures: ate_by_scenario.png and rpe_by_scenario.png (bars per scenario and mode, mean over
  /// seeds) and ate_vs_duration_<scenario>.png per sweep scenario. Returns the written paths;
  /// throws mcvio::InputError naming a file it cannot write.
  static std::vector<std::string> writePlots(const BenchmarkResult& result, const std::string& dir);

  /// DIR/bench.json, DIR/bench.md and (unless `plots` is false) the figures; creates DIR.
  static std::vector<std::string> write(const BenchmarkResult& result, const std::string& dir, bool plots = true);
};

}  // namespace mcvio::evaluation
