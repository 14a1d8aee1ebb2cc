#include "mcvio/estimator/anchor_stereo_factor.hpp"

namespace mcvio::estimator {

AnchorStereoFactor::AnchorStereoFactor(const Eigen::Vector2d& anchor_bearing, const Eigen::Vector2d& measured,
                                       const Eigen::Isometry3d& T_C1C0, double scale)
    : bearing_(anchor_bearing.x(), anchor_bearing.y(), 1.0),
      measured_(measured),
      R_C1C0_(T_C1C0.linear()),
      t_C1C0_(T_C1C0.translation()),
      scale_(scale) {}

bool AnchorStereoFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double rho = parameters[0][0];
  if (!(rho > 0)) return false;
  const Eigen::Vector3d p_C = R_C1C0_ * (bearing_ / rho) + t_C1C0_;
  if (p_C.z() < 1e-6) return false;
  const double inv_z = 1.0 / p_C.z();
  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = scale_ * (p_C.head<2>() * inv_z - measured_);
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Matrix<double, 2, 3> J_proj;
    J_proj << inv_z, 0, -p_C.x() * inv_z * inv_z, 0, inv_z, -p_C.y() * inv_z * inv_z;
    Eigen::Map<Eigen::Vector2d> J(jacobians[0]);
    J = scale_ * J_proj * R_C1C0_ * (-bearing_ / (rho * rho));
  }
  return true;
}

}  // namespace mcvio::estimator
