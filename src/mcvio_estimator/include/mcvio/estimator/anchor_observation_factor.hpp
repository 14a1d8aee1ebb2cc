#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/sized_cost_function.h>

namespace mcvio::estimator {

/// A landmark's observation in its own anchor frame. The landmark block is [alpha, beta, rho]:
/// the point in the anchor frame's cam0 is (alpha, beta, 1) / rho. For cam0 (T_CC0 = identity)
/// this pins the bearing; for cam1 it also fixes the metric depth through the stereo baseline,
/// which makes scale observable from a single frame. Residual scaled like ReprojectionFactor.
class AnchorObservationFactor : public ceres::SizedCostFunction<2, 3> {
 public:
  /// @param measured undistorted normalised coordinates in the observing camera.
  /// @param T_CC0 anchor cam0 -> observing camera (p_C = T_CC0 p_C0); identity for cam0.
  AnchorObservationFactor(const Eigen::Vector2d& measured, const Eigen::Isometry3d& T_CC0, double scale);
  /// @param sqrt_information 2x2 whitening of the normalised residual, as in ReprojectionFactor.
  AnchorObservationFactor(const Eigen::Vector2d& measured, const Eigen::Isometry3d& T_CC0,
                          const Eigen::Matrix2d& sqrt_information);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Eigen::Vector2d measured_;
  Eigen::Matrix3d R_CC0_;
  Eigen::Vector3d t_CC0_;
  double scale_;
  Eigen::Matrix2d sqrt_information_;
  bool isotropic_ = true;
};

}  // namespace mcvio::estimator
