#pragma once
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

/// The few SO(3) helpers the detectors need (right perturbation: R Exp(d)).
namespace mcvio::conflict::so3 {

inline Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

inline Eigen::Matrix3d exp(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  if (theta < 1e-10) return Eigen::Matrix3d::Identity() + hat(w);
  return Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
}

inline Eigen::Vector3d log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

}  // namespace mcvio::conflict::so3
