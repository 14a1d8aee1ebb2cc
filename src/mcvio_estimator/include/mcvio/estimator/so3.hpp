#pragma once
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

/// Small SO(3) helpers used by preintegration and the factors (right-perturbation convention:
/// R ⊞ δ = R Exp(δ)).
namespace mcvio::estimator::so3 {

/// Skew-symmetric matrix [v]x so that [v]x w = v x w.
inline Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// Exponential map as a unit quaternion.
inline Eigen::Quaterniond expQuat(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  if (theta < 1e-8) {
    Eigen::Quaterniond q(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z());
    return q.normalized();
  }
  const Eigen::Vector3d axis = w / theta;
  return Eigen::Quaterniond(Eigen::AngleAxisd(theta, axis));
}

/// Exponential map as a rotation matrix.
inline Eigen::Matrix3d exp(const Eigen::Vector3d& w) { return expQuat(w).toRotationMatrix(); }

/// Logarithm of a unit quaternion (rotation vector, angle in [0, pi]).
inline Eigen::Vector3d logQuat(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in;
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const double sin_half = q.vec().norm();
  if (sin_half < 1e-10) return 2.0 * q.vec() / q.w();
  const double half = std::atan2(sin_half, q.w());
  return q.vec() * (2.0 * half / sin_half);
}

/// Logarithm of a rotation matrix.
inline Eigen::Vector3d log(const Eigen::Matrix3d& R) { return logQuat(Eigen::Quaterniond(R)); }

/// Right Jacobian of SO(3): Exp(w + d) ~= Exp(w) Exp(Jr(w) d).
inline Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  const Eigen::Matrix3d W = hat(w);
  if (theta < 1e-5) return Eigen::Matrix3d::Identity() - 0.5 * W + W * W / 6.0;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() - (1.0 - std::cos(theta)) / t2 * W +
         (theta - std::sin(theta)) / (t2 * theta) * W * W;
}

/// Inverse of the right Jacobian: Log(Exp(w) Exp(d)) ~= w + JrInv(w) d.
inline Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  const Eigen::Matrix3d W = hat(w);
  if (theta < 1e-5) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 12.0;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + 0.5 * W +
         (1.0 / t2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta))) * W * W;
}

}  // namespace mcvio::estimator::so3
