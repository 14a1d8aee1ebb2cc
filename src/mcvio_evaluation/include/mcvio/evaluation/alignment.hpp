#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/evaluation/stamped_pose.hpp"

namespace mcvio::evaluation {

/// How an estimate is brought into the ground truth's world frame before absolute errors.
enum class Alignment {
  kNone,         ///< compare as is
  kSe3,          ///< rotation + translation (Umeyama, no scale): the best rigid fit
  kPositionYaw,  ///< rotation about gravity (world z) + translation: the 4 DoF VIO cannot observe
};

/// "none", "se3", "posyaw".
const char* toString(Alignment alignment);
/// Inverse of toString; throws std::invalid_argument listing the accepted names.
Alignment alignmentFromString(const std::string& name);

/// T minimising sum |gt_i - T * est_i|^2 over rigid motions (Umeyama 1991 without scale,
/// closed form by SVD, reflections excluded). One point gives a pure translation.
/// Throws std::invalid_argument if the lists differ in size or are empty.
Eigen::Isometry3d alignSe3(const std::vector<Eigen::Vector3d>& estimate,
                           const std::vector<Eigen::Vector3d>& ground_truth);

/// The same minimum over rotations about z and translations (closed form: the yaw is the
/// atan2 of the centred horizontal cross and dot sums; z shifts by the mean difference).
Eigen::Isometry3d alignPositionYaw(const std::vector<Eigen::Vector3d>& estimate,
                                   const std::vector<Eigen::Vector3d>& ground_truth);

/// Dispatches on `alignment` (kNone gives the identity).
Eigen::Isometry3d align(Alignment alignment, const std::vector<Eigen::Vector3d>& estimate,
                        const std::vector<Eigen::Vector3d>& ground_truth);

struct AlignmentOptions {
  /// Positions fix the rotation only if they spread out: a device at rest (or moving along one
  /// line, for SE(3)) leaves it arbitrary. Below this spread [m] the rotation is taken from the
  /// orientations instead. The spread is that of the ground-truth positions (so every run of a
  /// sequence is aligned the same way): the RMS distance from their mean along the second
  /// principal axis (SE(3)) or the first horizontal one (position+yaw). 0.1 m keeps the
  /// position-based rotation error of centimetre-accurate runs under a few degrees.
  double min_position_spread_m = 0.1;
};

struct AlignmentResult {
  Eigen::Isometry3d T_gt_est = Eigen::Isometry3d::Identity();
  /// True if the positions did not spread enough and the rotation is the chordal mean of
  /// R_gt_i R_est_i^T (SE(3)) or its best yaw (position+yaw); the translation still matches the
  /// position means.
  bool rotation_from_orientations = false;
  double position_spread_m = 0;  ///< the ground truth's spread compared with the threshold
};

/// Alignment of poses paired by index: the position-based closed forms above, or the
/// orientation-based rotation when the positions are degenerate (see AlignmentOptions).
AlignmentResult alignPoses(Alignment alignment, const std::vector<StampedPose>& estimate,
                           const std::vector<StampedPose>& ground_truth,
                           const AlignmentOptions& options = {});

}  // namespace mcvio::evaluation
