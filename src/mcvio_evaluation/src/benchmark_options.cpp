#include "mcvio/evaluation/benchmark_options.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/sim/scenario_options.hpp"

namespace mcvio::evaluation {

namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}

template <typename T>
bool hasDuplicates(std::vector<T> v) {
  std::sort(v.begin(), v.end());
  return std::adjacent_find(v.begin(), v.end()) != v.end();
}

}  // namespace

BenchmarkOptions BenchmarkOptions::quick() {
  BenchmarkOptions o;
  o.modes = {"reference", "auto"};
  o.scenarios = {"none", "elevator"};
  o.sequence_duration_s = 25.0;
  o.onset_s = 8.0;
  o.conflict_duration_s = 8.0;
  o.sweep_durations_s.clear();
  return o;
}

void BenchmarkOptions::validate() const {
  require(!modes.empty(), "modes: at least one mode is needed");
  for (const auto& m : modes) {
    try {
      conflict::resolutionModeFromString(m, "modes");
    } catch (const InputError& e) {
      throw std::invalid_argument(e.what());
    }
  }
  require(std::find(modes.begin(), modes.end(), "reference") != modes.end(),
          "modes: must include 'reference', the baseline every reduction and cost is measured against");
  require(!hasDuplicates(modes), "modes: a mode is listed twice");
  for (const auto* list : {&scenarios, &sweep_scenarios}) {
    for (const auto& s : *list) {
      try {
        sim::scenarioKindFromString(s);
      } catch (const InputError& e) {
        throw std::invalid_argument(std::string(list == &scenarios ? "scenarios" : "sweep_scenarios") + ": " + e.what());
      }
    }
  }
  require(!hasDuplicates(scenarios), "scenarios: a scenario is listed twice");
  require(!seeds.empty(), "seeds: at least one seed is needed");
  require(!hasDuplicates(seeds), "seeds: a seed is listed twice");
  require(std::isfinite(sequence_duration_s) && sequence_duration_s >= 5 && sequence_duration_s <= 3600,
          "sequence_duration_s: must be in [5, 3600]");
  require(std::isfinite(onset_s) && onset_s >= 2, "onset_s: must be at least 2 s (the estimator initialises first)");
  require(std::isfinite(conflict_duration_s) && conflict_duration_s > 0, "conflict_duration_s: must be positive");
  require(onset_s + conflict_duration_s <= sequence_duration_s,
          "conflict_duration_s: onset_s + conflict_duration_s must not exceed sequence_duration_s");
  for (double d : sweep_durations_s)
    require(std::isfinite(d) && d >= 0 && d <= 600, "sweep_durations_s: each must be in [0, 600]");
  require(!hasDuplicates(sweep_durations_s), "sweep_durations_s: a duration is listed twice");
  require(sweep_durations_s.empty() || !sweep_scenarios.empty(), "sweep_scenarios: empty while sweep_durations_s is not");
  for (const auto& s : sweep_scenarios)
    require(s == "elevator" || s == "vehicle",
            "sweep_scenarios: '" + s + "' has no ride whose duration can be swept (elevator, vehicle)");
  require(std::isfinite(sweep_tail_s) && sweep_tail_s >= 0, "sweep_tail_s: must not be negative");
  require(sweep_elevator_speed_mps > 0 && sweep_vehicle_speed_mps > 0, "sweep_*_speed_mps: must be positive");
  require(std::isfinite(rpe_delta_s) && rpe_delta_s > 0, "rpe_delta_s: must be positive");
  require(jobs >= 1 && jobs <= 64, "jobs: must be in [1, 64]");
  try {
    features.validate();
  } catch (const InputError& e) {
    throw std::invalid_argument(std::string("features: ") + e.what());
  }
  try {
    estimator.validate();
  } catch (const std::exception& e) {
    throw std::invalid_argument(std::string("estimator: ") + e.what());
  }
  const auto& t = targets;
  require(t.min_tpr >= 0 && t.min_tpr <= 1, "targets.min_tpr: must be in [0, 1]");
  require(t.max_fpr >= 0 && t.max_fpr <= 1, "targets.max_fpr: must be in [0, 1]");
  require(t.ride_displacement_tolerance_percent >= 0, "targets.ride_displacement_tolerance_percent: must not be negative");
  require(t.secondary_motion_tolerance_percent >= 0, "targets.secondary_motion_tolerance_percent: must not be negative");
}

}  // namespace mcvio::evaluation
