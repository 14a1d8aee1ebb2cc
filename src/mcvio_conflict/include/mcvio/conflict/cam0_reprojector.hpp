#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/conflict/relative_motion.hpp"

namespace mcvio::conflict {

/// Reprojection of a point of body r into cam0 of frame k under a relative motion, and its
/// linearisation: the one residual the pose solver, the landmark test and the region split share.
class Cam0Reprojector {
 public:
  struct Linearisation {
    Eigen::Vector3d X_k;                   ///< the point in body k
    Eigen::Vector2d residual;              ///< predicted minus observed [px]
    Eigen::Matrix<double, 2, 3> J_point;   ///< d residual / d X_k
    Eigen::Matrix<double, 2, 6> J_motion;  ///< d residual / d [dtheta, dt] (R * Exp(dtheta), t + dt)
  };

  explicit Cam0Reprojector(const RigGeometry& rig) : T_CB_(rig.T_BC0.inverse()), focal_px_(rig.focal_px) {}

  /// @param n0_k normalised cam0 observation in frame k.
  /// @return false when the point is behind cam0 or closer than 5 cm (no usable projection).
  bool linearise(const RelativeMotion& motion, const Eigen::Vector3d& X_r, const Eigen::Vector2d& n0_k,
                 Linearisation* out) const;

  const Eigen::Isometry3d& T_CB() const { return T_CB_; }
  double focalPx() const { return focal_px_; }

 private:
  Eigen::Isometry3d T_CB_;
  double focal_px_;
};

}  // namespace mcvio::conflict
