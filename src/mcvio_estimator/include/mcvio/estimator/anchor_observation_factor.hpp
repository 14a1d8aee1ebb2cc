#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/sized_cost_function.h>

namespace mcvio::estimator {

/// The right camera's observation of a landmark in the landmark's own anchor frame: depends only on
/// the inverse depth (through the fixed cam0 -> cam1 extrinsics), which makes metric depth
/// observable from a single stereo frame. Parameter block: inverse depth (1). Residual scaled like
/// ReprojectionFactor.
class AnchorStereoFactor : public ceres::SizedCostFunction<2, 1> {
 public:
  /// @param T_C1C0 cam0 -> cam1 transform (p_C1 = T_C1C0 p_C0).
  AnchorStereoFactor(const Eigen::Vector2d& anchor_bearing, const Eigen::Vector2d& measured,
                     const Eigen::Isometry3d& T_C1C0, double scale);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Eigen::Vector3d bearing_;
  Eigen::Vector2d measured_;
  Eigen::Matrix3d R_C1C0_;
  Eigen::Vector3d t_C1C0_;
  double scale_;
};

}  // namespace mcvio::estimator
