#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/sized_cost_function.h>

namespace mcvio::estimator {

/// Reprojection of an anchored inverse-depth landmark into camera c of another frame.
/// Parameter blocks: anchor pose (7), observing pose (7), landmark [alpha, beta, rho] (3), the
/// point in the anchor frame's cam0 being (alpha, beta, 1) / rho. Residual: (projected - measured)
/// normalised coordinates times scale = focal_length_px / sigma_px, i.e. whitened pixel error;
/// on a wide lens times a 2x2 square-root information instead (the lens's pixel Jacobian where the
/// feature was seen over sigma_px), since a pixel there spans different normalised lengths radially
/// and tangentially. Analytic Jacobians.
class ReprojectionFactor : public ceres::SizedCostFunction<2, 7, 7, 3> {
 public:
  /// @param measured undistorted normalised coordinates in the observing camera.
  /// @param T_BC0 anchor camera (cam0) to body; @param T_BC observing camera to body.
  ReprojectionFactor(const Eigen::Vector2d& measured, const Eigen::Isometry3d& T_BC0, const Eigen::Isometry3d& T_BC,
                     double scale);
  /// @param sqrt_information 2x2 whitening of the normalised residual (pixel Jacobian / sigma_px).
  ReprojectionFactor(const Eigen::Vector2d& measured, const Eigen::Isometry3d& T_BC0, const Eigen::Isometry3d& T_BC,
                     const Eigen::Matrix2d& sqrt_information);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// Point in the observing camera; false when it is not in front of the camera.
  bool pointInCamera(const double* anchor_pose, const double* pose, const double* landmark, Eigen::Vector3d* p_C) const;

 private:
  Eigen::Vector2d measured_;
  Eigen::Matrix3d R_BC0_, R_BC_, R_CB_;
  Eigen::Vector3d t_BC0_, t_BC_;
  double scale_;
  Eigen::Matrix2d sqrt_information_;
  bool isotropic_ = true;  ///< sqrt_information_ = scale_ * I: the scalar path, bit for bit as before
};

}  // namespace mcvio::estimator
