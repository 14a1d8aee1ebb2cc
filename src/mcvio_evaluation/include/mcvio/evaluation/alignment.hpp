#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

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

}  // namespace mcvio::evaluation
