#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mcvio/estimator/estimator_options.hpp"
#include "mcvio/sim/feature_simulator.hpp"

namespace mcvio::evaluation {

/// The MC-VIO targets (DESIGN.md, issue 6) a benchmark checks every MC-VIO run against.
struct BenchmarkTargets {
  /// Conflict scenarios: ATE (position+yaw RMSE) at least this much lower than `reference` [%].
  double conflict_ate_reduction_percent = 80.0;
  /// Conflict scenarios: RPE (1 s translation RMSE) at least this much lower [%].
  double conflict_rpe_reduction_percent = 40.0;
  /// Clean sequences: ATE at most this much higher than `reference` [%].
  double clean_max_ate_increase_percent = 5.0;
  /// Per-frame detection: TPR at least this at an FPR of at most max_fpr.
  double min_tpr = 0.95;
  double max_fpr = 0.02;
  /// Elevator: estimated vertical displacement of the ride within this share of the truth [%].
  double ride_displacement_tolerance_percent = 5.0;
  /// Elevator: the cabin's own motion (the secondary frame's vertical displacement) within this
  /// share of the ride's truth [%]; vehicle: the secondary frame's translation within this share
  /// of the travel.
  double secondary_motion_tolerance_percent = 10.0;
  /// Backend CPU per frame at most this much above the reference without its detectors [%].
  double max_added_cost_percent = 20.0;
};

/// What `mcvio bench` runs: every scenario x seed x mode at feature level (FeatureSimulator ->
/// SlidingWindowEstimator), plus a sweep of the conflict duration. Defaults are the full suite.
struct BenchmarkOptions {
  /// Resolution modes; must contain "reference", the baseline of every comparison.
  std::vector<std::string> modes = {"reference", "imu", "selective", "auto"};
  /// Scenario names as sim::scenarioKindFromString accepts them; may be empty (only the sweep, or
  /// only the recorded sequences of an image-level run).
  std::vector<std::string> scenarios = {"none", "elevator", "vehicle", "self_occlusion", "pedestrian", "slow_object"};
  std::vector<std::uint64_t> seeds = {1};
  double sequence_duration_s = 60.0;  ///< length of each scenario sequence
  double onset_s = 20.0;              ///< conflict onset after the first frame
  double conflict_duration_s = 15.0;  ///< conflict length of the scenario sequences
  /// ATE versus conflict duration: these durations [s] for each sweep scenario, first seed only
  /// (it is the costliest part). Empty: no sweep. 0 keeps the scene but nothing moves.
  std::vector<double> sweep_durations_s = {0, 10, 20, 30, 40};
  std::vector<std::string> sweep_scenarios = {"elevator", "vehicle"};
  /// Sweep sequences last onset_s + duration + sweep_tail_s, so the estimator is seen recovering.
  double sweep_tail_s = 15.0;
  /// Sweep rides keep a constant mean speed, so a longer conflict also travels further: the
  /// elevator's default ride is 12 m in 15 s, the vehicle's 4 m/s.
  double sweep_elevator_speed_mps = 0.8;
  double sweep_vehicle_speed_mps = 4.0;
  /// The FeatureSimulator marks tracks on moving bodies as inconsistent from the ground truth.
  /// A real frontend cannot know that, so by default those labels are cleared before the
  /// estimator sees the frames; true keeps them (an oracle frontend).
  bool oracle_track_labels = false;
  double rpe_delta_s = 1.0;  ///< RPE pair separation [s]
  int jobs = 1;              ///< sequences simulated and estimated in parallel
  sim::FeatureSimulatorOptions features;
  /// Feature level: the estimator's options in every run (the mode is set per run, and
  /// observation_sigma_px always equals the simulator's features.pixel_noise_sigma).
  estimator::EstimatorOptions estimator;
  BenchmarkTargets targets;

  /// A small suite for tests and a first look: 25 s sequences, conflict 8..16 s, no sweep.
  static BenchmarkOptions quick();
  /// Throws std::invalid_argument naming the option (e.g. "modes: unknown mode 'x'").
  void validate() const;
};

}  // namespace mcvio::evaluation
