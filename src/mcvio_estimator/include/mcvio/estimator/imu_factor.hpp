#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include "mcvio/estimator/imu_preintegrator.hpp"

namespace mcvio::estimator {

/// Preintegrated IMU factor between consecutive frames i and j (15-dim residual, whitened by the
/// preintegration's square-root information). Parameter blocks: pose_i [p, q] (7), speed-bias_i
/// [v, bg, ba] (9), pose_j (7), speed-bias_j (9). The last six residual rows are the bias random
/// walk between the frames. The deltas are bias-corrected to first order with the preintegration's
/// Jacobians; the estimator re-integrates when the bias moves further than its threshold.
/// Everything needed is copied at construction, so the factor does not refer to the preintegrator.
class ImuFactor {
 public:
  ImuFactor(const ImuPreintegrator& pre, const Eigen::Vector3d& gravity);

  /// Ceres cost function with automatic derivatives (few IMU factors per window, so autodiff is cheap).
  static ceres::CostFunction* create(const ImuPreintegrator& pre, const Eigen::Vector3d& gravity);

  template <typename T>
  bool operator()(const T* pose_i, const T* sb_i, const T* pose_j, const T* sb_j, T* residual) const {
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Vec3> p_i(pose_i), v_i(sb_i), bg_i(sb_i + 3), ba_i(sb_i + 6);
    const Eigen::Map<const Vec3> p_j(pose_j), v_j(sb_j), bg_j(sb_j + 3), ba_j(sb_j + 6);
    const Eigen::Map<const Eigen::Quaternion<T>> q_i(pose_i + 3), q_j(pose_j + 3);

    const Vec3 dbg = bg_i - bg_lin_.cast<T>();
    const Vec3 dba = ba_i - ba_lin_.cast<T>();
    const Vec3 phi = dR_dbg_.cast<T>() * dbg;
    T aa[3] = {phi[0], phi[1], phi[2]};
    T qc[4];  // ceres order w, x, y, z
    ceres::AngleAxisToQuaternion(aa, qc);
    const Eigen::Quaternion<T> dq_corr = delta_q_.cast<T>() * Eigen::Quaternion<T>(qc[0], qc[1], qc[2], qc[3]);
    const Vec3 dv_corr = delta_v_.cast<T>() + dV_dbg_.cast<T>() * dbg + dV_dba_.cast<T>() * dba;
    const Vec3 dp_corr = delta_p_.cast<T>() + dP_dbg_.cast<T>() * dbg + dP_dba_.cast<T>() * dba;

    const Eigen::Quaternion<T> q_err = dq_corr.conjugate() * (q_i.conjugate() * q_j);
    const T qe[4] = {q_err.w(), q_err.x(), q_err.y(), q_err.z()};
    T r_theta[3];
    ceres::QuaternionToAngleAxis(qe, r_theta);

    const T dt = T(dt_);
    const Vec3 g = gravity_.cast<T>();
    const Eigen::Quaternion<T> q_i_inv = q_i.conjugate();
    Eigen::Matrix<T, 15, 1> r;
    r.template segment<3>(0) = Vec3(r_theta[0], r_theta[1], r_theta[2]);
    r.template segment<3>(3) = q_i_inv * (v_j - v_i - g * dt) - dv_corr;
    r.template segment<3>(6) = q_i_inv * (p_j - p_i - v_i * dt - T(0.5) * g * dt * dt) - dp_corr;
    r.template segment<3>(9) = bg_j - bg_i;
    r.template segment<3>(12) = ba_j - ba_i;
    Eigen::Map<Eigen::Matrix<T, 15, 1>> out(residual);
    out = sqrt_info_.cast<T>() * r;
    return true;
  }

 private:
  double dt_;
  Eigen::Vector3d gravity_;
  Eigen::Quaterniond delta_q_;
  Eigen::Vector3d delta_v_, delta_p_;
  Eigen::Matrix3d dR_dbg_, dV_dbg_, dV_dba_, dP_dbg_, dP_dba_;
  Eigen::Vector3d bg_lin_, ba_lin_;
  Eigen::Matrix<double, 15, 15> sqrt_info_;
};

}  // namespace mcvio::estimator
