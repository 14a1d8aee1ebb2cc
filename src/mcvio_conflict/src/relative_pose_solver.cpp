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
  const double s2_px = options_.observation_sigma_px * options_.observation_sigma_px;
  // Residual weight relative to pixel noise alone: sigma^2 (sigma^2 I + a a^T)^-1, a = the pixel
  // shift of one depth sigma at r (Sherman-Morrison). The identity without depth uncertainty.
  auto weight = [&](const TrackedPoint& p, const Eigen::Matrix3d& R, const Eigen::Matrix<double, 2, 3>& Jp_f) {
    Eigen::Matrix2d W = Eigen::Matrix2d::Identity();
    if (!options_.depth_weighting || !(p.depth_sigma_r > 0)) return W;
    const Eigen::Vector2d a = Jp_f * (T_CB.linear() * (R.transpose() * p.ray_r)) * p.depth_sigma_r;
    W -= a * a.transpose() / (s2_px + a.squaredNorm());
    return W;
  };
  // Point i in cam0 of k under (R, t): its pixel residual and d(normalised image)/d(X_c); false
  // behind the camera.
  auto project = [&](const TrackedPoint& p, const Eigen::Matrix3d& R, const Eigen::Vector3d& t, Eigen::Vector3d* X_k,
                     Eigen::Vector2d* r, Eigen::Matrix<double, 2, 3>* Jp) {
    *X_k = R.transpose() * (p.X_r - t);
    const Eigen::Vector3d X_c = T_CB * *X_k;
    if (X_c.z() < 0.05) return false;
    const double iz = 1.0 / X_c.z();
    *r = f * (X_c.head<2>() * iz - p.n0_k);
    *Jp << iz, 0, -X_c.x() * iz * iz, 0, iz, -X_c.y() * iz * iz;
    return true;
  };
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
        Eigen::Vector3d X_k;
        Eigen::Vector2d r;
        Eigen::Matrix<double, 2, 3> Jp;
        if (!project(points[i], R, t, &X_k, &r, &Jp)) continue;
        Eigen::Matrix<double, 3, 6> Jx;
        Jx.leftCols<3>() = so3::hat(X_k);   // d X_k / d dtheta (right perturbation of R)
        Jx.rightCols<3>() = -R.transpose();  // d X_k / d dt
        const Eigen::Matrix<double, 2, 6> J = f * Jp * T_CB.linear() * Jx;
        const Eigen::Matrix2d W = weight(points[i], R, f * Jp);
        double w = 1.0;
        const double e = std::sqrt(r.dot(W * r));
        if (robust && e > options_.huber_px) w = options_.huber_px / e;
        H += w * J.transpose() * W * J;
        g += w * J.transpose() * W * r;
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
    Eigen::Vector3d X_k;
    Eigen::Vector2d r;
    Eigen::Matrix<double, 2, 3> Jp;
    const double e = project(points[i], R, t, &X_k, &r, &Jp) ? std::sqrt(r.dot(weight(points[i], R, f * Jp) * r)) : 1e9;
    use[i] = e < options_.outlier_px ? 1 : 0;
    if (use[i]) {
      ++inliers;
      sum2 += e * e;
    }
  }
  if (inliers < options_.min_points) return res;
  if (!pass(false, 3)) return res;
  // A posteriori variance: the fit's own scatter (residuals under their weights) covers what the
  // weights do not model.
  const double dof = std::max(1, inliers - 6);
  const double s2 = std::max(s2_px, sum2 / dof);
  res.motion.R = R;
  res.motion.t = t;
  res.motion.covariance = s2 * H.inverse();
  res.inliers = inliers;
  res.rms_px = std::sqrt(sum2 / inliers);
  res.valid = res.motion.covariance.allFinite();
  return res;
}

}  // namespace mcvio::conflict
