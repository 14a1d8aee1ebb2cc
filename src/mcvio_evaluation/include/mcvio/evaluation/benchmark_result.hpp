#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "mcvio/evaluation/benchmark_options.hpp"
#include "mcvio/evaluation/detector_record.hpp"
#include "mcvio/evaluation/trajectory.hpp"

namespace mcvio::evaluation {

/// One simulated sequence of a benchmark.
struct BenchmarkSequence {
  std::string name;       ///< e.g. "elevator_s1", "sweep_vehicle_20s_s1"
  std::string scenario;   ///< sim scenario name
  std::uint64_t seed = 1;
  double duration_s = 0;          ///< sequence length
  double onset_s = 0;
  double conflict_duration_s = 0; ///< length of the conflicting motion (0: none)
  double travel_m = 0;            ///< SimulatorOptions::scenario.travel_m (0 = scenario default)
  bool sweep = false;             ///< part of the ATE-versus-duration sweep

  /// Scenarios whose labels mark a conflict (all but "none" and zero-length sweeps).
  bool hasConflict() const { return scenario != "none" && conflict_duration_s > 0; }
};

/// The raw output of one mode on one sequence, before evaluation: whatever produced it (the
/// feature-level estimator here, an image-level `mcvio run` elsewhere).
struct BenchmarkModeRun {
  std::string mode;
  Trajectory estimate;                  ///< body in world per tracked frame (final, revisions applied)
  Trajectory estimate_online;           ///< the per-frame output where revisions changed it; else empty
  std::vector<DetectorRecord> detector; ///< per tracked frame
  Trajectory secondary;                 ///< the conflicting frame S in world while it is tracked
  std::vector<double> cpu_ms;           ///< backend CPU per frame
  std::vector<double> conflict_ms;      ///< conflict stage per frame (wall clock)
  std::size_t frames = 0;               ///< frames fed
  int resets = 0;
  double wall_s = 0;
};

/// Pass/fail of the targets that apply to one run; empty optionals do not apply.
struct BenchmarkChecks {
  std::optional<bool> ate_reduction;     ///< conflict scenarios
  std::optional<bool> rpe_reduction;     ///< conflict scenarios
  std::optional<bool> clean_ate;         ///< "none"
  std::optional<bool> detection;         ///< TPR (with conflict) and FPR
  std::optional<bool> ride_displacement; ///< elevator
  std::optional<bool> secondary_motion;  ///< elevator: the cabin's own motion
  std::optional<bool> vehicle_motion;    ///< vehicle: the vehicle's own motion
  std::optional<bool> cost;
  /// All applicable checks pass (true when none applies).
  bool allPass() const;
};

/// Everything measured for one mode on one sequence. NaN = not measurable (written null / n/a).
struct BenchmarkRun {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string mode;
  std::size_t frames = 0;          ///< feature frames fed
  std::size_t tracked_frames = 0;  ///< frames with a tracking estimate (the evaluated poses)
  int resets = 0;
  double wall_s = 0;               ///< simulation excluded

  double ate_posyaw_m = kNaN;      ///< RMSE after position+yaw alignment
  double ate_posyaw_online_m = kNaN;  ///< the same for the per-frame output (= ate_posyaw_m if unrevised)
  double ate_se3_m = kNaN;         ///< RMSE after SE(3) alignment
  double ate_posyaw_in_conflict_m = kNaN;  ///< over frames labelled in conflict, whole-run alignment
  double rpe_translation_m = kNaN; ///< RMSE over pairs rpe_delta_s apart
  double rpe_rotation_deg = kNaN;

  std::size_t tp = 0, fp = 0, tn = 0, fn = 0;
  double tpr = kNaN, fpr = kNaN;
  /// The same against the run's conflict intervals in hindsight (DetectionResult::hindsight).
  double hindsight_tpr = kNaN, hindsight_fpr = kNaN;
  /// Over the sequence's labelled span (DetectionResult::labelledSpan): seconds from its first
  /// labelled frame to the first detection, and from its last labelled frame to the end of the last
  /// detection.
  double onset_delay_s = kNaN, release_lag_s = kNaN;
  /// ROC of the detector scores: the best TPR with FPR <= targets.max_fpr and its score name.
  double roc_best_tpr = kNaN;
  std::string roc_best_score;
  double auc_propagated = kNaN, auc_fraction = kNaN, auc_evidence = kNaN;

  double cpu_median_ms = kNaN;     ///< backend CPU per frame (EstimatorTimings::cpu_total_ms)
  double cpu_mean_ms = kNaN;
  double conflict_mean_ms = kNaN;  ///< wall clock of the conflict stage per frame

  /// Elevator: vertical displacement over the labelled interval (first to last labelled tracked
  /// frame), truth and estimate, and the secondary frame's z at the last labelled frame where it
  /// was valid (identity at the detected interval start).
  double ride_truth_dz_m = kNaN, ride_estimate_dz_m = kNaN, ride_error_percent = kNaN;
  double secondary_dz_m = kNaN, secondary_error_percent = kNaN;
  /// Vehicle: the body's displacement over the labelled interval (first to last labelled tracked
  /// frame) and the secondary frame's translation at the last labelled frame where it was valid,
  /// turned into the ground truth's frame by the run's position+yaw alignment; the error is the
  /// length of their difference over the truth's length [%].
  double travel_truth_m = kNaN, secondary_travel_m = kNaN, secondary_travel_error_percent = kNaN;

  /// Versus `reference` on the same sequence: 100 (ref - run) / ref, positive = less error.
  double ate_reduction_percent = kNaN;
  double ate_in_conflict_reduction_percent = kNaN;
  double rpe_reduction_percent = kNaN;
  /// Mean CPU per frame above the reference's without its conflict stage (the reference runs
  /// the detectors too, reporting only): 100 (cpu - base) / base, base = ref cpu - ref conflict.
  double added_cost_percent = kNaN;

  BenchmarkChecks checks;
};

/// All modes on one sequence.
struct BenchmarkSequenceResult {
  BenchmarkSequence sequence;
  std::size_t frames = 0;
  std::size_t conflict_frames = 0;  ///< frames labelled in conflict
  double simulate_s = 0;            ///< wall clock of the feature simulation
  std::vector<BenchmarkRun> runs;   ///< in options.modes order
  /// ATE pos+yaw of `reference` on the same sequence without its conflict (image level: the
  /// injected overlay's base sequence, or the clean office rendered along the same trajectory with
  /// the same IMU), NaN when there is none. No method can get below the clean run's own error, so
  /// the largest reachable reduction is 100 (reference - floor) / reference.
  double clean_floor_ate_m = BenchmarkRun::kNaN;
  const BenchmarkRun* find(const std::string& mode) const;
};

/// One target over every run it applies to, for one mode.
struct BenchmarkTargetSummary {
  std::string target;     ///< e.g. "conflict ATE reduction >= 80%"
  std::string mode;
  std::size_t passed = 0, total = 0;
  double worst = BenchmarkRun::kNaN;  ///< the least favourable measured value
  std::string worst_sequence;
  bool pass() const { return total > 0 && passed == total; }
};

/// A whole benchmark: options, every sequence and the target summary.
struct BenchmarkResult {
  std::string level = "features";  ///< "features" or "images"
  BenchmarkOptions options;
  /// Image level: the rig folder the scenarios were rendered with (empty: EuRoC V1_01's) and the
  /// renderer's texture filter (sim::TextureFilter's name).
  std::string render_rig;
  std::string texture_filter = "isotropic";
  std::vector<BenchmarkSequenceResult> sequences;  ///< scenario sequences, then the sweep
  std::vector<BenchmarkTargetSummary> targets;
  double wall_s = 0;
};

}  // namespace mcvio::evaluation
