#include "mcvio/conflict/landmark_conflict_detector.hpp"

#include <cmath>
#include <unordered_map>

#include <Eigen/Dense>

#include "mcvio/conflict/so3_math.hpp"

namespace mcvio::conflict {

namespace {

/// Least-squares rigid transform Q = R P + t (Umeyama / Kabsch without scale).
bool fitRigid(const std::vector<Eigen::Vector3d>& P, const std::vector<Eigen::Vector3d>& Q, Eigen::Isometry3d* T) {
  const std::size_t n = P.size();
  if (n < 3) return false;
  Eigen::Vector3d mp = Eigen::Vector3d::Zero(), mq = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    mp += P[i];
    mq += Q[i];
  }
  mp /= static_cast<double>(n);
  mq /= static_cast<double>(n);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i) C += (Q[i] - mq) * (P[i] - mp).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1;
  const Eigen::Matrix3d R = svd.matrixU() * D * svd.matrixV().transpose();
  T->setIdentity();
  T->linear() = R;
  T->translation() = mq - R * mp;
  return T->matrix().allFinite();
}

}  // namespace

LandmarkConflictDetector::Result LandmarkConflictDetector::test(const std::vector<TrackedPoint>& points,
                                                                const RelativeMotion& imu) const {
  Result res;
  const Eigen::Isometry3d T_CB = rig_.T_BC0.inverse();
  const double f = rig_.focal_px;
  const double s_obs2 = options_.observation_sigma_px * options_.observation_sigma_px;
  const Eigen::Matrix3d Rt = imu.R.transpose();
  for (const auto& p : points) {
    const Eigen::Vector3d X_k = Rt * (p.X_r - imu.t);
    const Eigen::Vector3d X_c = T_CB * X_k;
    if (X_c.z() < 0.05) continue;
    const double iz = 1.0 / X_c.z();
    const Eigen::Vector2d r = f * (X_c.head<2>() * iz - p.n0_k);
    Eigen::Matrix<double, 2, 3> Jp;
    Jp << iz, 0, -X_c.x() * iz * iz, 0, iz, -X_c.y() * iz * iz;
    const Eigen::Matrix<double, 2, 3> J_xk = f * Jp * T_CB.linear();
    Eigen::Matrix<double, 3, 6> Jm;
    Jm.leftCols<3>() = so3::hat(X_k);
    Jm.rightCols<3>() = -Rt;
    const Eigen::Matrix<double, 2, 6> J_motion = J_xk * Jm;
    const double lateral = p.depth_r * options_.observation_sigma_px / f;
    const Eigen::Matrix3d S_xr = p.depth_sigma_r * p.depth_sigma_r * p.ray_r * p.ray_r.transpose() +
                                 lateral * lateral * (Eigen::Matrix3d::Identity() - p.ray_r * p.ray_r.transpose());
    const Eigen::Matrix<double, 2, 3> J_point = J_xk * Rt;
    Eigen::Matrix2d S = J_motion * imu.covariance * J_motion.transpose() + J_point * S_xr * J_point.transpose();
    S += s_obs2 * Eigen::Matrix2d::Identity();
    Verdict v;
    v.track_id = p.track_id;
    v.chi2 = r.dot(S.ldlt().solve(r));
    if (!std::isfinite(v.chi2)) continue;
    v.inconsistent = v.chi2 > options_.landmark_chi2_threshold;
    res.verdicts.push_back(v);
    ++res.tested;
    res.inconsistent += v.inconsistent ? 1 : 0;
  }
  res.fraction = res.tested > 0 ? static_cast<double>(res.inconsistent) / res.tested : 0.0;
  if (res.inconsistent >= 3) fitGroup(points, imu, &res);
  return res;
}

void LandmarkConflictDetector::fitGroup(const std::vector<TrackedPoint>& points, const RelativeMotion& imu,
                                        Result* res) const {
  std::unordered_map<std::uint64_t, const TrackedPoint*> by_id;
  for (const auto& p : points) by_id[p.track_id] = &p;
  std::vector<Eigen::Vector3d> P, Q, ray;
  std::vector<double> var_along, var_lateral;
  const Eigen::Vector3d cam_center = rig_.T_BC0.translation();
  const double s2 = options_.coherence_sigma_m * options_.coherence_sigma_m;
  int group = 0;
  for (const auto& v : res->verdicts) {
    if (!v.inconsistent) continue;
    ++group;
    const TrackedPoint& p = *by_id.at(v.track_id);
    if (!p.has_X_k) continue;
    P.push_back(imu.toCurrent(p.X_r));
    Q.push_back(p.X_k);
    // Stereo points are precise across the ray and poor along it.
    const Eigen::Vector3d d = p.X_k - cam_center;
    const double z = d.norm();
    ray.push_back(d / z);
    var_along.push_back(s2 + p.depth_sigma_r * p.depth_sigma_r + p.depth_sigma_k * p.depth_sigma_k);
    const double lat = 2.0 * z * options_.observation_sigma_px / rig_.focal_px;
    var_lateral.push_back(s2 + lat * lat);
  }
  auto fits = [&](const Eigen::Isometry3d& T, std::size_t i) {
    const Eigen::Vector3d e = T * P[i] - Q[i];
    const double along = e.dot(ray[i]);
    const double lateral2 = (e - along * ray[i]).squaredNorm();
    return along * along / var_along[i] + lateral2 / var_lateral[i] < 11.34;  // chi-square 3 dof, 99 %
  };
  const std::size_t n = P.size();
  if (n < 3 || group == 0) return;
  // Deterministic RANSAC: minimal samples drawn by a fixed linear congruential sequence.
  std::uint64_t state = 0x9E3779B97F4A7C15ULL;
  auto next = [&](std::size_t m) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<std::size_t>((state >> 33) % m);
  };
  std::vector<char> best_in;
  int best = 0;
  const int trials = n <= 6 ? 20 : 60;
  for (int trial = 0; trial < trials; ++trial) {
    const std::size_t a = next(n), b = next(n), c = next(n);
    if (a == b || b == c || a == c) continue;
    Eigen::Isometry3d T;
    if (!fitRigid({P[a], P[b], P[c]}, {Q[a], Q[b], Q[c]}, &T)) continue;
    std::vector<char> in(n, 0);
    int count = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (fits(T, i)) {
        in[i] = 1;
        ++count;
      }
    if (count > best) {
      best = count;
      best_in = in;
    }
  }
  if (best < 3) return;
  std::vector<Eigen::Vector3d> Pi, Qi;
  for (std::size_t i = 0; i < n; ++i)
    if (best_in[i]) {
      Pi.push_back(P[i]);
      Qi.push_back(Q[i]);
    }
  Eigen::Isometry3d T;
  if (fitRigid(Pi, Qi, &T)) res->T_group = T;
  res->coherent_count = best;
  // Disagreeing tracks without a stereo point cannot be tested; judge the ones that can.
  res->coherence = static_cast<double>(best) / static_cast<double>(n);
}

}  // namespace mcvio::conflict
