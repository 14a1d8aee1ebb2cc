#include "mcvio/evaluation/alignment.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace mcvio::evaluation {

namespace {

void checkSizes(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  if (a.size() != b.size()) {
    throw std::invalid_argument("alignment: " + std::to_string(a.size()) + " estimate and " +
                                std::to_string(b.size()) + " ground-truth positions");
  }
  if (a.empty()) throw std::invalid_argument("alignment: no positions to align");
}

Eigen::Vector3d mean(const std::vector<Eigen::Vector3d>& v) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (const auto& x : v) m += x;
  return m / static_cast<double>(v.size());
}

}  // namespace

const char* toString(Alignment alignment) {
  switch (alignment) {
    case Alignment::kNone: return "none";
    case Alignment::kSe3: return "se3";
    case Alignment::kPositionYaw: return "posyaw";
  }
  return "none";
}

Alignment alignmentFromString(const std::string& name) {
  if (name == "none") return Alignment::kNone;
  if (name == "se3") return Alignment::kSe3;
  if (name == "posyaw") return Alignment::kPositionYaw;
  throw std::invalid_argument("alignment '" + name + "' is not one of none, se3, posyaw");
}

Eigen::Isometry3d alignSe3(const std::vector<Eigen::Vector3d>& estimate,
                           const std::vector<Eigen::Vector3d>& ground_truth) {
  checkSizes(estimate, ground_truth);
  const Eigen::Vector3d mu_e = mean(estimate), mu_g = mean(ground_truth);
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();  // cross-covariance gt x est
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    H += (ground_truth[i] - mu_g) * (estimate[i] - mu_e).transpose();
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (estimate.size() > 1 && H.norm() > 0) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;
    T.linear() = svd.matrixU() * S * svd.matrixV().transpose();
  }
  T.translation() = mu_g - T.linear() * mu_e;
  return T;
}

Eigen::Isometry3d alignPositionYaw(const std::vector<Eigen::Vector3d>& estimate,
                                   const std::vector<Eigen::Vector3d>& ground_truth) {
  checkSizes(estimate, ground_truth);
  const Eigen::Vector3d mu_e = mean(estimate), mu_g = mean(ground_truth);
  // Maximise sum g . Rz(yaw) e over the centred points: c * sum(dot) + s * sum(cross_z).
  double dot = 0, cross = 0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const Eigen::Vector3d e = estimate[i] - mu_e, g = ground_truth[i] - mu_g;
    dot += g.x() * e.x() + g.y() * e.y();
    cross += g.y() * e.x() - g.x() * e.y();
  }
  const double yaw = (dot == 0 && cross == 0) ? 0.0 : std::atan2(cross, dot);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = mu_g - T.linear() * mu_e;
  return T;
}

Eigen::Isometry3d align(Alignment alignment, const std::vector<Eigen::Vector3d>& estimate,
                        const std::vector<Eigen::Vector3d>& ground_truth) {
  switch (alignment) {
    case Alignment::kSe3: return alignSe3(estimate, ground_truth);
    case Alignment::kPositionYaw: return alignPositionYaw(estimate, ground_truth);
    case Alignment::kNone: break;
  }
  checkSizes(estimate, ground_truth);
  return Eigen::Isometry3d::Identity();
}

AlignmentResult alignPoses(Alignment alignment, const std::vector<StampedPose>& estimate,
                           const std::vector<StampedPose>& ground_truth, const AlignmentOptions& options) {
  std::vector<Eigen::Vector3d> est_p, gt_p;
  est_p.reserve(estimate.size());
  gt_p.reserve(ground_truth.size());
  for (const auto& p : estimate) est_p.push_back(p.p);
  for (const auto& p : ground_truth) gt_p.push_back(p.p);
  checkSizes(est_p, gt_p);
  AlignmentResult r;
  if (alignment == Alignment::kNone) return r;

  const Eigen::Vector3d mu_e = mean(est_p), mu_g = mean(gt_p);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : gt_p) cov += (p - mu_g) * (p - mu_g).transpose();
  cov /= static_cast<double>(gt_p.size());
  double spread = 0;
  if (alignment == Alignment::kSe3) {
    const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues();  // ascending
    spread = std::sqrt(std::max(0.0, ev(1)));
  } else {
    const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov.topLeftCorner<2, 2>()).eigenvalues();
    spread = std::sqrt(std::max(0.0, ev(1)));
  }
  r.position_spread_m = spread;
  if (spread >= options.min_position_spread_m) {
    r.T_gt_est = align(alignment, est_p, gt_p);
    return r;
  }
  r.rotation_from_orientations = true;
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();  // sum of R_gt R_est^T
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    M += ground_truth[i].q.toRotationMatrix() * estimate[i].q.toRotationMatrix().transpose();
  }
  Eigen::Matrix3d R;
  if (alignment == Alignment::kSe3) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;
    R = svd.matrixU() * S * svd.matrixV().transpose();
  } else {
    // argmax over yaw of trace(Rz(yaw)^T M).
    const double yaw = std::atan2(M(1, 0) - M(0, 1), M(0, 0) + M(1, 1));
    R = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  r.T_gt_est.linear() = R;
  r.T_gt_est.translation() = mu_g - R * mu_e;
  return r;
}

}  // namespace mcvio::evaluation
