#include "mcvio/conflict/relative_pose_solver.hpp"

#include <algorithm>
#include <cmath>

#include "mcvio/conflict/so3_math.hpp"

namespace mcvio::conflict {

RelativePoseSolver::Result RelativePoseSolver::solve(const std::vector<TrackedPoint>& points,
                                                     const RelativeMotion& initial) const {
  Result res;
  if (static_cast<int>(points.size()) < options_.min_points) return res;
  const Eigen::Isometry3d T_CB = rig_.T_BC0.inverse();
  const double f = rig_.focal_px;
  Eigen::Matrix3d R = initial.R;
  Eigen::Vector3d t = initial.t;
  std::vector<char> use(points.size(), 1);
  Eigen::Matrix<double, 6, 6> H;

  auto pass = [&](bool robust, int iterations) {
    for (int it = 0; it < iterations; ++it) {
      H.setZero();
      Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
      int n = 0;
      for (std::size_t i = 0; i < points.size(); ++i) {
        if (!use[i]) continue;
        const Eigen::Vector3d X_k = R.transpose() * (points[i].X_r - t);
        const Eigen::Vector3d X_c = T_CB * X_k;
        if (X_c.z() < 0.05) continue;
        const double iz = 1.0 / X_c.z();
        const Eigen::Vector2d r = f * (X_c.head<2>() * iz - points[i].n0_k);
        Eigen::Matrix<double, 2, 3> Jp;
        Jp << iz, 0, -X_c.x() * iz * iz, 0, iz, -X_c.y() * iz * iz;
        Eigen::Matrix<double, 3, 6> Jx;
        Jx.leftCols<3>() = so3::hat(X_k);   // d X_k / d dtheta (right perturbation of R)
        Jx.rightCols<3>() = -R.transpose();  // d X_k / d dt
        const Eigen::Matrix<double, 2, 6> J = f * Jp * T_CB.linear() * Jx;
        double w = 1.0;
        const double e = r.norm();
        if (robust && e > options_.huber_px) w = options_.huber_px / e;
        H += w * J.transpose() * J;
        g += w * J.transpose() * r;
        ++n;
      }
      if (n < options_.min_points) return false;
      const Eigen::Matrix<double, 6, 1> dx = H.ldlt().solve(-g);
      if (!dx.allFinite()) return false;
      R = R * so3::exp(dx.head<3>());
      t += dx.tail<3>();
      if (dx.norm() < 1e-9) break;
    }
    return true;
  };

  if (!pass(true, options_.iterations)) return res;
  // Re-fit on inliers only so a moving minority does not bias the answer.
  double sum2 = 0;
  int inliers = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d X_c = T_CB * (R.transpose() * (points[i].X_r - t));
    const double e = X_c.z() > 0.05 ? (f * (X_c.head<2>() / X_c.z() - points[i].n0_k)).norm() : 1e9;
    use[i] = e < options_.outlier_px ? 1 : 0;
    if (use[i]) {
      ++inliers;
      sum2 += e * e;
    }
  }
  if (inliers < options_.min_points) return res;
  if (!pass(false, 3)) return res;
  // A posteriori variance: stereo depth errors of the points at r add to the pixel noise, and
  // the fit's own scatter measures both.
  const double dof = std::max(1, inliers - 6);
  const double s2 = std::max(options_.observation_sigma_px * options_.observation_sigma_px, sum2 / dof);
  res.motion.R = R;
  res.motion.t = t;
  res.motion.covariance = s2 * H.inverse();
  res.inliers = inliers;
  res.rms_px = std::sqrt(sum2 / inliers);
  res.valid = res.motion.covariance.allFinite();
  return res;
}

}  // namespace mcvio::conflict
