#include "mcvio/estimator/anchor_observation_factor.hpp"

namespace mcvio::estimator {

AnchorObservationFactor::AnchorObservationFactor(const Eigen::Vector2d& measured, const Eigen::Isometry3d& T_CC0,
                                                 double scale)
    : measured_(measured),
      R_CC0_(T_CC0.linear()),
      t_CC0_(T_CC0.translation()),
      scale_(scale),
      sqrt_information_(scale * Eigen::Matrix2d::Identity()) {}

AnchorObservationFactor::AnchorObservationFactor(const Eigen::Vector2d& measured, const Eigen::Isometry3d& T_CC0,
                                                 const Eigen::Matrix2d& sqrt_information)
    : AnchorObservationFactor(measured, T_CC0, 1.0) {
  sqrt_information_ = sqrt_information;
  isotropic_ = false;
}

bool AnchorObservationFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* l = parameters[0];
  const double rho = l[2];
  if (!(rho > 0)) return false;
  const Eigen::Vector3d p_C0(l[0] / rho, l[1] / rho, 1.0 / rho);
  const Eigen::Vector3d p_C = R_CC0_ * p_C0 + t_CC0_;
  if (p_C.z() < 1e-6) return false;
  const double inv_z = 1.0 / p_C.z();
  Eigen::Map<Eigen::Vector2d> r(residuals);
  if (isotropic_) r = scale_ * (p_C.head<2>() * inv_z - measured_);
  else r = sqrt_information_ * (p_C.head<2>() * inv_z - measured_);
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Matrix<double, 2, 3> J_proj;
    J_proj << inv_z, 0, -p_C.x() * inv_z * inv_z, 0, inv_z, -p_C.y() * inv_z * inv_z;
    Eigen::Matrix3d J_l;
    J_l << 1 / rho, 0, -l[0] / (rho * rho), 0, 1 / rho, -l[1] / (rho * rho), 0, 0, -1 / (rho * rho);
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J(jacobians[0]);
    if (isotropic_) J = scale_ * J_proj * R_CC0_ * J_l;
    else J = sqrt_information_ * J_proj * R_CC0_ * J_l;
  }
  return true;
}

}  // namespace mcvio::estimator
