#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/sized_cost_function.h>

namespace mcvio::estimator {

/// Reprojection of a landmark stored as inverse depth along its bearing in the anchor frame's cam0,
/// observed by camera c of another frame. Parameter blocks: anchor pose (7), observing pose (7),
/// inverse depth (1). Residual: (projected - measured) normalised coordinates times
/// scale = focal_length_px / sigma_px, i.e. whitened pixel error. Analytic Jacobians.
class ReprojectionFactor : public ceres::SizedCostFunction<2, 7, 7, 1> {
 public:
  /// @param anchor_bearing undistorted normalised (x/z, y/z) of the anchor observation in cam0.
  /// @param measured undistorted normalised coordinates in the observing camera.
  /// @param T_BC0 anchor camera (cam0) to body; @param T_BC observing camera to body.
  ReprojectionFactor(const Eigen::Vector2d& anchor_bearing, const Eigen::Vector2d& measured,
                     const Eigen::Isometry3d& T_BC0, const Eigen::Isometry3d& T_BC, double scale);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// Point in the observing camera; false when it is not in front of the camera.
  bool pointInCamera(const double* anchor_pose, const double* pose, double inverse_depth,
                     Eigen::Vector3d* p_C) const;

 private:
  Eigen::Vector3d bearing_;
  Eigen::Vector2d measured_;
  Eigen::Matrix3d R_BC0_, R_BC_;
  Eigen::Vector3d t_BC0_, t_BC_;
  double scale_;
};

}  // namespace mcvio::estimator
