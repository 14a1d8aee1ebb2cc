#include "mcvio/estimator/imu_factor.hpp"

#include "mcvio/estimator/pose_manifold.hpp"
#include "mcvio/estimator/so3.hpp"

namespace mcvio::estimator {

ImuFactor::ImuFactor(const ImuPreintegrator& pre, const Eigen::Vector3d& gravity)
    : dt_(pre.deltaTime()),
      gravity_(gravity),
      delta_q_(pre.deltaQ()),
      delta_v_(pre.deltaV()),
      delta_p_(pre.deltaP()),
      dR_dbg_(pre.dR_dbg()),
      dV_dbg_(pre.dV_dbg()),
      dV_dba_(pre.dV_dba()),
      dP_dbg_(pre.dP_dbg()),
      dP_dba_(pre.dP_dba()),
      bg_lin_(pre.linearizationBias().gyro),
      ba_lin_(pre.linearizationBias().accel),
      sqrt_info_(pre.sqrtInformation()) {}

ceres::CostFunction* ImuFactor::create(const ImuPreintegrator& pre, const Eigen::Vector3d& gravity) {
  return new ImuFactor(pre, gravity);
}

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  using Eigen::Matrix3d;
  using Eigen::Vector3d;
  const Eigen::Map<const Vector3d> p_i(parameters[0]), p_j(parameters[2]);
  const Eigen::Map<const Eigen::Quaterniond> q_i(parameters[0] + 3), q_j(parameters[2] + 3);
  const Eigen::Map<const Vector3d> v_i(parameters[1]), bg_i(parameters[1] + 3), ba_i(parameters[1] + 6);
  const Eigen::Map<const Vector3d> v_j(parameters[3]), bg_j(parameters[3] + 3), ba_j(parameters[3] + 6);

  const Vector3d dbg = bg_i - bg_lin_, dba = ba_i - ba_lin_;
  const Vector3d phi = dR_dbg_ * dbg;
  const Eigen::Quaterniond dq_corr = delta_q_ * so3::expQuat(phi);
  const Vector3d dv_corr = delta_v_ + dV_dbg_ * dbg + dV_dba_ * dba;
  const Vector3d dp_corr = delta_p_ + dP_dbg_ * dbg + dP_dba_ * dba;

  const Matrix3d R_i_T = q_i.toRotationMatrix().transpose();
  const Eigen::Quaterniond q_err = dq_corr.conjugate() * (q_i.conjugate() * q_j);
  const Vector3d v_term = R_i_T * (v_j - v_i - gravity_ * dt_);
  const Vector3d p_term = R_i_T * (p_j - p_i - v_i * dt_ - 0.5 * gravity_ * dt_ * dt_);

  Eigen::Matrix<double, 15, 1> r;
  r.segment<3>(0) = so3::logQuat(q_err);
  r.segment<3>(3) = v_term - dv_corr;
  r.segment<3>(6) = p_term - dp_corr;
  r.segment<3>(9) = bg_j - bg_i;
  r.segment<3>(12) = ba_j - ba_i;
  Eigen::Map<Eigen::Matrix<double, 15, 1>> out(residuals);
  out = sqrt_info_ * r;
  if (jacobians == nullptr) return true;

  // Raw (unwhitened) Jacobians in the tangent spaces; rotation errors are right perturbations,
  // R <- R Exp(d), so R_i^T x moves by hat(R_i^T x) d and Log(E) by JrInv(Log E) times E's increment.
  const Matrix3d Jr_inv = so3::rightJacobianInverse(r.segment<3>(0));
  using Tangent = Eigen::Matrix<double, 15, 6>;
  using SpeedBias = Eigen::Matrix<double, 15, 9>;
  // Whitens a pose block's tangent Jacobian and lifts its rotation columns to quaternion coordinates.
  auto writePose = [this](const Tangent& J, const Eigen::Quaterniond& q, double* out) {
    const Tangent W = sqrt_info_ * J;
    Eigen::Map<Eigen::Matrix<double, 15, 7, Eigen::RowMajor>> out_J(out);
    out_J.leftCols<3>() = W.leftCols<3>();
    out_J.rightCols<4>() = W.rightCols<3>() * PoseManifold::liftQuaternionJacobian(q);
  };
  if (jacobians[0] != nullptr) {
    Tangent J = Tangent::Zero();
    J.block<3, 3>(0, 3) = -Jr_inv * (q_j.conjugate() * q_i).toRotationMatrix();
    J.block<3, 3>(3, 3) = so3::hat(v_term);
    J.block<3, 3>(6, 0) = -R_i_T;
    J.block<3, 3>(6, 3) = so3::hat(p_term);
    writePose(J, q_i, jacobians[0]);
  }
  if (jacobians[1] != nullptr) {
    SpeedBias J = SpeedBias::Zero();
    J.block<3, 3>(0, 3) = -Jr_inv * q_err.conjugate().toRotationMatrix() * so3::rightJacobian(phi) * dR_dbg_;
    J.block<3, 3>(3, 0) = -R_i_T;
    J.block<3, 3>(3, 3) = -dV_dbg_;
    J.block<3, 3>(3, 6) = -dV_dba_;
    J.block<3, 3>(6, 0) = -R_i_T * dt_;
    J.block<3, 3>(6, 3) = -dP_dbg_;
    J.block<3, 3>(6, 6) = -dP_dba_;
    J.block<3, 3>(9, 3) = -Matrix3d::Identity();
    J.block<3, 3>(12, 6) = -Matrix3d::Identity();
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> out_J(jacobians[1]);
    out_J = sqrt_info_ * J;
  }
  if (jacobians[2] != nullptr) {
    Tangent J = Tangent::Zero();
    J.block<3, 3>(0, 3) = Jr_inv;
    J.block<3, 3>(6, 0) = R_i_T;
    writePose(J, q_j, jacobians[2]);
  }
  if (jacobians[3] != nullptr) {
    SpeedBias J = SpeedBias::Zero();
    J.block<3, 3>(3, 0) = R_i_T;
    J.block<3, 3>(9, 3) = Matrix3d::Identity();
    J.block<3, 3>(12, 6) = Matrix3d::Identity();
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> out_J(jacobians[3]);
    out_J = sqrt_info_ * J;
  }
  return true;
}

}  // namespace mcvio::estimator
