#include "mcvio/conflict/cam0_reprojector.hpp"

#include "mcvio/conflict/so3_math.hpp"

namespace mcvio::conflict {

bool Cam0Reprojector::linearise(const RelativeMotion& motion, const Eigen::Vector3d& X_r,
                                const Eigen::Vector2d& n0_k, Linearisation* out) const {
  const Eigen::Matrix3d Rt = motion.R.transpose();
  out->X_k = Rt * (X_r - motion.t);
  const Eigen::Vector3d X_c = T_CB_ * out->X_k;
  if (X_c.z() < 0.05) return false;
  const double iz = 1.0 / X_c.z();
  out->residual = focal_px_ * (X_c.head<2>() * iz - n0_k);
  Eigen::Matrix<double, 2, 3> Jp;
  Jp << iz, 0, -X_c.x() * iz * iz, 0, iz, -X_c.y() * iz * iz;
  out->J_point = focal_px_ * Jp * T_CB_.linear();
  Eigen::Matrix<double, 3, 6> Jx;
  Jx.leftCols<3>() = so3::hat(out->X_k);  // right perturbation of R
  Jx.rightCols<3>() = -Rt;
  out->J_motion = out->J_point * Jx;
  return true;
}

}  // namespace mcvio::conflict
