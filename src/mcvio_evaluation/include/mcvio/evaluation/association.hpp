#pragma once
#include <cstddef>
#include <vector>

#include "mcvio/evaluation/trajectory.hpp"

namespace mcvio::evaluation {

/// How estimate poses find their ground truth.
struct AssociationOptions {
  enum class Method {
    /// Ground truth interpolated at each estimate time (EuRoC ground truth is dense, 200 Hz).
    kInterpolate,
    /// The ground-truth pose nearest in time, within max_time_difference_s.
    kNearest,
  };
  Method method = Method::kInterpolate;
  /// kInterpolate: never bridge ground-truth holes longer than this [s] (EuRoC has some).
  double max_interpolation_gap_s = 0.1;
  /// kNearest: largest accepted time difference [s]; half a 200 Hz period is exact-match only.
  double max_time_difference_s = 0.02;

  /// Throws std::invalid_argument naming the field if a value is out of range.
  void validate() const;
};

/// Estimate and ground-truth poses paired at the estimate's times.
struct AssociatedPoses {
  std::vector<StampedPose> estimate;      ///< estimate poses that found ground truth
  std::vector<StampedPose> ground_truth;  ///< ground truth at the same index (time of estimate)
  std::size_t unmatched = 0;              ///< estimate poses without ground truth
  std::size_t size() const { return estimate.size(); }
};

/// Pairs every estimate pose with ground truth (see AssociationOptions). Estimate poses outside
/// the ground truth's time span or in its holes are counted in `unmatched`.
AssociatedPoses associate(const Trajectory& estimate, const Trajectory& ground_truth,
                          const AssociationOptions& options = {});

}  // namespace mcvio::evaluation
