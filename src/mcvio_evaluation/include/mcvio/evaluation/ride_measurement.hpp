#pragma once
#include <limits>

#include <Eigen/Core>

#include "mcvio/evaluation/conflict_label_timeline.hpp"
#include "mcvio/evaluation/trajectory.hpp"

namespace mcvio::evaluation {

/// How far a ride carried the device, and how far the estimate and the conflicting frame say it
/// did, over the labelled interval as a run saw it: from its first to its last tracked frame
/// labelled in conflict. The elevator's figures are vertical (gravity fixes z in both worlds);
/// the vehicle's are whole displacements, the estimate's world turned into the ground truth's.
struct RideMeasurement {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  bool valid = false;  ///< two labelled tracked frames with ground truth
  double truth_dz_m = kNaN, estimate_dz_m = kNaN, dz_error_percent = kNaN;
  /// The secondary frame's z at the last labelled frame where it was valid (it starts as the
  /// world at the detected interval start, so its translation is the ride's).
  double secondary_dz_m = kNaN, secondary_dz_error_percent = kNaN;
  /// Whole displacement: the body's truth, and the secondary frame's translation turned by
  /// R_gt_est; the error is the length of their difference over the truth's.
  double travel_truth_m = kNaN, secondary_travel_m = kNaN, secondary_travel_error_percent = kNaN;

  /// `R_gt_est`: the rotation of the estimate's world into the ground truth's (the position+yaw
  /// alignment's); `secondary` may be empty (no conflicting frame tracked).
  static RideMeasurement measure(const Trajectory& estimate, const Trajectory& secondary, const Trajectory& ground_truth,
                                 const ConflictLabelTimeline& labels, const Eigen::Matrix3d& R_gt_est,
                                 double label_tolerance_s = 0.02);
};

}  // namespace mcvio::evaluation
