#pragma once
#include <cstddef>
#include <vector>

#include "mcvio/evaluation/association.hpp"
#include "mcvio/evaluation/error_statistics.hpp"
#include "mcvio/evaluation/trajectory.hpp"

namespace mcvio::evaluation {

/// Relative pose error over a fixed time or travelled distance.
struct RpeOptions {
  enum class Delta {
    kTime,      ///< pairs `delta` seconds apart
    kDistance,  ///< pairs `delta` metres apart along the ground-truth path
  };
  Delta unit = Delta::kTime;
  /// 1 s / 1 m: a few frames of drift, and EuRoC rooms are a few metres across.
  double delta = 1.0;
  /// A pair's actual separation may exceed `delta` by this fraction (frames are discrete and
  /// some are skipped); longer ones are dropped rather than mixed into the statistics.
  double tolerance = 0.1;
  AssociationOptions association;

  static RpeOptions time(double seconds);
  static RpeOptions distance(double metres);
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

/// RPE of an estimate: for every associated pose i (all pairs, not disjoint segments) the first
/// later pose j at least `delta` away, and the error E = (G_i^-1 G_j)^-1 (E_i^-1 E_j).
/// Needs no alignment: relative motions do not depend on the world frame.
struct RpeResult {
  RpeOptions options;
  ErrorStatistics translation;  ///< |translation of E| [m]
  ErrorStatistics rotation;     ///< angle of E [deg]
  /// Per pair, in time order.
  std::vector<Timestamp> start_times;
  std::vector<double> translation_errors;
  std::vector<double> rotation_errors_deg;
};

/// Throws mcvio::InputError naming both sources if no estimate pose has ground truth; a run
/// shorter than delta gives count 0 (NaN statistics).
RpeResult computeRpe(const Trajectory& estimate, const Trajectory& ground_truth,
                     const RpeOptions& options = {});

}  // namespace mcvio::evaluation
