#include "mcvio/estimator/reprojection_factor.hpp"

#include "mcvio/estimator/pose_manifold.hpp"
#include "mcvio/estimator/so3.hpp"

namespace mcvio::estimator {

namespace {
constexpr double kMinDepth = 1e-6;
}

ReprojectionFactor::ReprojectionFactor(const Eigen::Vector2d& measured, const Eigen::Isometry3d& T_BC0,
                                       const Eigen::Isometry3d& T_BC, double scale)
    : measured_(measured),
      R_BC0_(T_BC0.linear()),
      R_BC_(T_BC.linear()),
      R_CB_(T_BC.linear().transpose()),
      t_BC0_(T_BC0.translation()),
      t_BC_(T_BC.translation()),
      scale_(scale),
      sqrt_information_(scale * Eigen::Matrix2d::Identity()) {}

ReprojectionFactor::ReprojectionFactor(const Eigen::Vector2d& measured, const Eigen::Isometry3d& T_BC0,
                                       const Eigen::Isometry3d& T_BC, const Eigen::Matrix2d& sqrt_information)
    : ReprojectionFactor(measured, T_BC0, T_BC, 1.0) {
  sqrt_information_ = sqrt_information;
  isotropic_ = false;
}

bool ReprojectionFactor::pointInCamera(const double* anchor_pose, const double* pose, const double* l,
                                       Eigen::Vector3d* p_C) const {
  if (!(l[2] > 0)) return false;
  const Eigen::Map<const Eigen::Vector3d> p_a(anchor_pose), p_t(pose);
  const Eigen::Map<const Eigen::Quaterniond> q_a(anchor_pose + 3), q_t(pose + 3);
  const Eigen::Vector3d p_Ba = R_BC0_ * (Eigen::Vector3d(l[0], l[1], 1.0) / l[2]) + t_BC0_;
  const Eigen::Vector3d p_W = q_a * p_Ba + p_a;
  const Eigen::Vector3d p_Bt = q_t.conjugate() * (p_W - p_t);
  *p_C = R_CB_ * (p_Bt - t_BC_);
  return p_C->z() > kMinDepth;
}

bool ReprojectionFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* l = parameters[2];
  const double rho = l[2];
  if (!(rho > 0)) return false;
  const Eigen::Map<const Eigen::Vector3d> p_a(parameters[0]), p_t(parameters[1]);
  const Eigen::Map<const Eigen::Quaterniond> q_a(parameters[0] + 3), q_t(parameters[1] + 3);
  const Eigen::Matrix3d R_a = q_a.toRotationMatrix(), R_t = q_t.toRotationMatrix();
  const double inv_rho = 1.0 / rho;
  const Eigen::Vector3d p_C0a(l[0] * inv_rho, l[1] * inv_rho, inv_rho);
  const Eigen::Vector3d p_Ba = R_BC0_ * p_C0a + t_BC0_;
  const Eigen::Vector3d p_W = R_a * p_Ba + p_a;
  const Eigen::Vector3d p_Bt = R_t.transpose() * (p_W - p_t);
  const Eigen::Vector3d p_C = R_CB_ * (p_Bt - t_BC_);
  if (p_C.z() < kMinDepth) return false;
  const double inv_z = 1.0 / p_C.z();
  Eigen::Matrix<double, 2, 3> J_proj;
  if (isotropic_) {
    residuals[0] = scale_ * (p_C.x() * inv_z - measured_.x());
    residuals[1] = scale_ * (p_C.y() * inv_z - measured_.y());
    if (jacobians == nullptr) return true;
    const double s_z = scale_ * inv_z;
    J_proj << s_z, 0, -p_C.x() * inv_z * s_z, 0, s_z, -p_C.y() * inv_z * s_z;
  } else {
    Eigen::Map<Eigen::Vector2d> r(residuals);
    r = sqrt_information_ * (p_C.head<2>() * inv_z - measured_);
    if (jacobians == nullptr) return true;
    J_proj << inv_z, 0, -p_C.x() * inv_z * inv_z, 0, inv_z, -p_C.y() * inv_z * inv_z;
    J_proj = sqrt_information_ * J_proj;
  }
  const Eigen::Matrix<double, 2, 3> J_pb = J_proj * R_CB_;            // d r / d p_Bt
  const Eigen::Matrix<double, 2, 3> J_pw = J_pb * R_t.transpose();   // d r / d p_W
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> J(jacobians[0]);
    J.leftCols<3>() = J_pw;
    J.rightCols<4>() = (-(J_pw * R_a) * so3::hat(p_Ba)) * PoseManifold::liftQuaternionJacobian(q_a);
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> J(jacobians[1]);
    J.leftCols<3>() = -J_pw;
    J.rightCols<4>() = (J_pb * so3::hat(p_Bt)) * PoseManifold::liftQuaternionJacobian(q_t);
  }
  if (jacobians[2] != nullptr) {
    Eigen::Matrix3d J_l;
    const double ir2 = inv_rho * inv_rho;
    J_l << inv_rho, 0, -l[0] * ir2, 0, inv_rho, -l[1] * ir2, 0, 0, -ir2;
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J(jacobians[2]);
    J = J_pw * (R_a * R_BC0_) * J_l;
  }
  return true;
}

}  // namespace mcvio::estimator
