#pragma once
#include <cstddef>
#include <functional>
#include <vector>

#include "mcvio/evaluation/alignment.hpp"
#include "mcvio/evaluation/association.hpp"
#include "mcvio/evaluation/error_statistics.hpp"
#include "mcvio/evaluation/trajectory.hpp"

namespace mcvio::evaluation {

struct AteOptions {
  AssociationOptions association;
  AlignmentOptions alignment;
};

/// Absolute trajectory error of an estimate after one alignment to ground truth.
struct AteResult {
  Alignment alignment = Alignment::kSe3;
  /// World change applied to the estimate: aligned = T_gt_est * estimate.
  Eigen::Isometry3d T_gt_est = Eigen::Isometry3d::Identity();
  /// The positions barely moved, so the alignment's rotation came from the orientations.
  bool rotation_from_orientations = false;
  double position_spread_m = 0;  ///< see AlignmentResult
  std::size_t unmatched = 0;  ///< estimate poses without ground truth (not in the errors)
  ErrorStatistics translation;  ///< |p_gt - p_aligned| [m]
  ErrorStatistics rotation;     ///< angle of q_gt^-1 * q_aligned [deg]

  /// Per associated pose, in time order (same index in every vector).
  std::vector<StampedPose> aligned_estimate;
  std::vector<StampedPose> ground_truth;  ///< at the estimate's times
  std::vector<double> translation_errors;
  std::vector<double> rotation_errors_deg;

  /// Statistics of the poses whose time `select` accepts (e.g. frames labelled in conflict),
  /// keeping the whole-run alignment.
  ErrorStatistics translationWithin(const std::function<bool(Timestamp)>& select) const;
  ErrorStatistics rotationWithin(const std::function<bool(Timestamp)>& select) const;
};

/// Associates `estimate` with `ground_truth`, aligns it (`alignment`, fitted on every associated
/// position; on the orientations for the rotation if the positions barely spread, see
/// AlignmentOptions) and measures the errors. Throws mcvio::InputError naming both sources if no
/// estimate pose has ground truth.
AteResult computeAte(const Trajectory& estimate, const Trajectory& ground_truth,
                     Alignment alignment, const AteOptions& options = {});

}  // namespace mcvio::evaluation
