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
  const Eigen::Matrix3d R_CB = T_CB.linear();
  const Eigen::Vector3d t_CB = T_CB.translation();
  const double f = rig_.focal_px;
  const double s2_px = options_.observation_sigma_px * options_.observation_sigma_px;
  Eigen::Matrix3d R = initial.R;
  Eigen::Vector3d t = initial.t;

  // Point p in cam0 of k under (R, t), with Rt = R^T and R_CB_Rt = R_CB R^T: its pixel residual
  // r, the whitening of r (W = I - beta a a^T) and, with `jacobian`, J = d r / d [dtheta, dt]; false
  // behind the camera. The weight is relative to pixel noise alone: sigma^2 (sigma^2 I + a a^T)^-1,
  // a = the pixel shift of one depth sigma at r (Sherman-Morrison); beta = 0 without depth
  // uncertainty.
  struct Linearized {
    Eigen::Vector2d r;
    Eigen::Vector2d a;
    double beta = 0;
    Eigen::Matrix<double, 2, 6> J;
    double whitenedNorm() const {
      const double ar = a.dot(r);
      return std::sqrt(std::max(0.0, r.squaredNorm() - beta * ar * ar));
    }
  };
  auto linearize = [&](const TrackedPoint& p, const Eigen::Matrix3d& Rt, const Eigen::Matrix3d& R_CB_Rt,
                       bool jacobian, Linearized* l) {
    const Eigen::Vector3d X_k = Rt * (p.X_r - t);
    const Eigen::Vector3d X_c = R_CB * X_k + t_CB;
    if (X_c.z() < 0.05) return false;
    const double iz = 1.0 / X_c.z();
    l->r = f * (X_c.head<2>() * iz - p.n0_k);
    // P: d pixel / d X_c.
    Eigen::Matrix<double, 2, 3> P;
    P << f * iz, 0, -f * X_c.x() * iz * iz, 0, f * iz, -f * X_c.y() * iz * iz;
    l->beta = 0;
    l->a.setZero();
    if (options_.depth_weighting && p.depth_sigma_r > 0) {
      l->a = P * (R_CB_Rt * p.ray_r) * p.depth_sigma_r;
      l->beta = 1.0 / (s2_px + l->a.squaredNorm());
    }
    if (jacobian) {
      const Eigen::Matrix<double, 2, 3> PR = P * R_CB;
      // d X_k / d dtheta = hat(X_k) (right perturbation of R): row i of PR hat(X_k) is PR_i x X_k.
      l->J.row(0).head<3>() = PR.row(0).transpose().cross(X_k).transpose();
      l->J.row(1).head<3>() = PR.row(1).transpose().cross(X_k).transpose();
      l->J.rightCols<3>() = -P * R_CB_Rt;  // d X_k / d dt = -R^T
    }
    return true;
  };
  std::vector<char> use(points.size(), 1);
  Eigen::Matrix<double, 6, 6> H;

  auto pass = [&](bool robust, int iterations) {
    for (int it = 0; it < iterations; ++it) {
      const Eigen::Matrix3d Rt = R.transpose();
      const Eigen::Matrix3d R_CB_Rt = R_CB * Rt;
      H.setZero();
      Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
      int n = 0;
      Linearized l;
      for (std::size_t i = 0; i < points.size(); ++i) {
        if (!use[i]) continue;
        if (!linearize(points[i], Rt, R_CB_Rt, true, &l)) continue;
        double w = 1.0;
        if (robust) {
          const double e = l.whitenedNorm();
          if (e > options_.huber_px) w = options_.huber_px / e;
        }
        // J^T W J = J^T J - beta u u^T with u = J^T a: three symmetric rank-one updates.
        const Eigen::Matrix<double, 6, 1> j0 = l.J.row(0).transpose(), j1 = l.J.row(1).transpose();
        const Eigen::Matrix<double, 6, 1> u = l.J.transpose() * l.a;
        const Eigen::Matrix<double, 6, 1> wj0 = w * j0, wj1 = w * j1, wu = (-w * l.beta) * u;
        for (int c = 0; c < 6; ++c)
          for (int r = 0; r <= c; ++r) H(r, c) += wj0[r] * j0[c] + wj1[r] * j1[c] + wu[r] * u[c];
        g += w * (l.J.transpose() * l.r - l.beta * l.a.dot(l.r) * u);
        ++n;
      }
      if (n < options_.min_points) return false;
      H.triangularView<Eigen::StrictlyLower>() = H.transpose();
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
  {
    const Eigen::Matrix3d Rt = R.transpose();
    const Eigen::Matrix3d R_CB_Rt = R_CB * Rt;
    Linearized l;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double e = linearize(points[i], Rt, R_CB_Rt, false, &l) ? l.whitenedNorm() : 1e9;
      use[i] = e < options_.outlier_px ? 1 : 0;
      if (use[i]) {
        ++inliers;
        sum2 += e * e;
      }
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
