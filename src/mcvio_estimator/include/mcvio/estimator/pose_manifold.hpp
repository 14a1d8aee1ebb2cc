#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/manifold.h>

namespace mcvio::estimator {

/// Pose parameter block [px, py, pz, qx, qy, qz, qw] (Eigen quaternion coefficient order), body to
/// world. Tangent [dp, dtheta] with dtheta a right (body-frame) perturbation:
///   p' = p + dp,  q' = q * Exp(dtheta).
/// Factors with analytic Jacobians compute them in the tangent space and lift the rotation part
/// with liftQuaternionJacobian(), so that ceres' product with PlusJacobian() gives them back exactly.
class PoseManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;

  /// d(q * Exp(dtheta)) / d(dtheta) at dtheta = 0, in (x, y, z, w) order (4x3).
  static Eigen::Matrix<double, 4, 3> quaternionPlusJacobian(const Eigen::Quaterniond& q);
  /// Left inverse of quaternionPlusJacobian (3x4): J_tangent * lift = J_ambient with
  /// J_ambient * quaternionPlusJacobian = J_tangent.
  static Eigen::Matrix<double, 3, 4> liftQuaternionJacobian(const Eigen::Quaterniond& q);
  /// Tangent-space difference y - x of two pose blocks ([dp, Log(q_x^-1 q_y)]).
  static Eigen::Matrix<double, 6, 1> difference(const double* y, const double* x);
};

}  // namespace mcvio::estimator
