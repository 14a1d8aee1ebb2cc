#pragma once
#include <ceres/autodiff_cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mcvio::estimator {

/// Relative rotation between two poses as vision measured it: residual
/// S * 2 vec(q_meas^-1 * q_i^-1 * q_j) (the small-angle rotation error), on pose blocks [p, q(x,y,z,w)].
/// Used inside an IMU-dominated conflict when the conflicting frame translates without turning.
struct RelativeRotationFactor {
  RelativeRotationFactor(const Eigen::Quaterniond& q_meas, const Eigen::Matrix3d& sqrt_information)
      : q_meas_(q_meas.normalized()), sqrt_info_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_i(pose_i + 3), q_j(pose_j + 3);
    const Eigen::Quaternion<T> dq = q_meas_.cast<T>().conjugate() * q_i.conjugate() * q_j;
    Eigen::Matrix<T, 3, 1> e = T(2.0) * dq.vec();
    if (dq.w() < T(0.0)) e = -e;
    Eigen::Map<Eigen::Matrix<T, 3, 1>> out(residual);
    out = sqrt_info_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* create(const Eigen::Quaterniond& q_meas, const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativeRotationFactor, 3, 7, 7>(
        new RelativeRotationFactor(q_meas, sqrt_information));
  }

 private:
  Eigen::Quaterniond q_meas_;
  Eigen::Matrix3d sqrt_info_;
};

}  // namespace mcvio::estimator
