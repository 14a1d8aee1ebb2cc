#include "mcvio/estimator/pose_manifold.hpp"

#include "mcvio/estimator/so3.hpp"

namespace mcvio::estimator {

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  Eigen::Map<const Eigen::Vector3d> p(x);
  Eigen::Map<const Eigen::Quaterniond> q(x + 3);
  Eigen::Map<const Eigen::Vector3d> dp(delta);
  Eigen::Map<const Eigen::Vector3d> dtheta(delta + 3);
  Eigen::Map<Eigen::Vector3d> p_out(x_plus_delta);
  Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta + 3);
  p_out = p + dp;
  q_out = (q * so3::expQuat(dtheta)).normalized();
  return true;
}

Eigen::Matrix<double, 4, 3> PoseManifold::quaternionPlusJacobian(const Eigen::Quaterniond& q) {
  Eigen::Matrix<double, 4, 3> J;
  J.topRows<3>() = 0.5 * (q.w() * Eigen::Matrix3d::Identity() + so3::hat(q.vec()));
  J.bottomRows<1>() = -0.5 * q.vec().transpose();
  return J;
}

Eigen::Matrix<double, 3, 4> PoseManifold::liftQuaternionJacobian(const Eigen::Quaterniond& q) {
  // 4 * quaternionPlusJacobian(q)^T: its columns are orthogonal with norm 1/2 for a unit q.
  Eigen::Matrix<double, 3, 4> L;
  const double w = 2.0 * q.w(), x = 2.0 * q.x(), y = 2.0 * q.y(), z = 2.0 * q.z();
  L << w, z, -y, -x,  //
      -z, w, x, -y,   //
      y, -x, w, -z;
  return L;
}

bool PoseManifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topLeftCorner<3, 3>().setIdentity();
  J.bottomRightCorner<4, 3>() = quaternionPlusJacobian(Eigen::Map<const Eigen::Quaterniond>(x + 3));
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<Eigen::Matrix<double, 6, 1>> out(y_minus_x);
  out = difference(y, x);
  return true;
}

bool PoseManifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topLeftCorner<3, 3>().setIdentity();
  J.bottomRightCorner<3, 4>() = liftQuaternionJacobian(Eigen::Map<const Eigen::Quaterniond>(x + 3));
  return true;
}

Eigen::Matrix<double, 6, 1> PoseManifold::difference(const double* y, const double* x) {
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = Eigen::Map<const Eigen::Vector3d>(y) - Eigen::Map<const Eigen::Vector3d>(x);
  const Eigen::Map<const Eigen::Quaterniond> qx(x + 3), qy(y + 3);
  d.tail<3>() = so3::logQuat(qx.conjugate() * qy);
  return d;
}

}  // namespace mcvio::estimator
