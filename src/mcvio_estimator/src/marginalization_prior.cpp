#include "mcvio/estimator/marginalization_prior.hpp"

#include <algorithm>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "mcvio/estimator/pose_manifold.hpp"

namespace mcvio::estimator {

namespace {

Eigen::VectorXd blockDifference(const MarginalizationPrior::Block& b, const double* x) {
  if (b.kind == BlockKind::kPose) return PoseManifold::difference(x, b.x_lin.data());
  Eigen::VectorXd d(b.size);
  for (int i = 0; i < b.size; ++i) d[i] = x[i] - b.x_lin[static_cast<std::size_t>(i)];
  return d;
}

}  // namespace

int MarginalizationPrior::tangentDimension() const {
  int n = 0;
  for (const auto& b : blocks) n += b.tangent_size;
  return n;
}

bool MarginalizationPrior::involves(const double* data) const {
  for (const auto& b : blocks)
    if (b.data == data) return true;
  return false;
}

void MarginalizationPrior::setCommonTranslationCovariance(const Eigen::Matrix3d& covariance) {
  // The rows' part along U = J G (G: a common translation) is the prior's information about it:
  // with U = W S V^T, J - W W^T J keeps every row orthogonal to it (an infinite uncertainty added
  // along the translation, Woodbury's limit). Three rows then anchor the last pose's position.
  const int n = tangentDimension();
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, 3);
  int off = 0, anchor = -1;
  for (const auto& b : blocks) {
    if (b.kind == BlockKind::kPose) {
      G.block<3, 3>(off, 0).setIdentity();
      anchor = off;
    }
    off += b.tangent_size;
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(0.5 * (covariance + covariance.transpose()));
  if (anchor < 0 || llt.info() != Eigen::Success || !covariance.allFinite()) return;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J * G, Eigen::ComputeThinU);
  const Eigen::VectorXd sv = svd.singularValues();
  int k = 0;
  while (k < sv.size() && sv[k] > 1e-12 * std::max(1.0, sv[0])) ++k;
  if (k > 0) {
    const Eigen::MatrixXd W = svd.matrixU().leftCols(k);
    J -= W * (W.transpose() * J);
    r -= W * (W.transpose() * r);
  }
  const Eigen::Matrix3d L_inv = llt.matrixL().solve(Eigen::Matrix3d::Identity());
  const Eigen::Index rows = J.rows();
  J.conservativeResize(rows + 3, Eigen::NoChange);
  J.bottomRows(3).setZero();
  J.block(rows, anchor, 3, 3) = L_inv;
  r.conservativeResize(rows + 3);
  r.tail(3).setZero();
}

Eigen::VectorXd MarginalizationPrior::evaluate() const {
  Eigen::VectorXd dx(tangentDimension());
  int off = 0;
  for (const auto& b : blocks) {
    dx.segment(off, b.tangent_size) = blockDifference(b, b.data);
    off += b.tangent_size;
  }
  return r + J * dx;
}

MarginalizationFactor::MarginalizationFactor(std::shared_ptr<const MarginalizationPrior> prior)
    : prior_(std::move(prior)) {
  set_num_residuals(static_cast<int>(prior_->r.size()));
  for (const auto& b : prior_->blocks) mutable_parameter_block_sizes()->push_back(b.size);
}

std::vector<double*> MarginalizationFactor::parameterBlocks() const {
  std::vector<double*> out;
  for (const auto& b : prior_->blocks) out.push_back(b.data);
  return out;
}

bool MarginalizationFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const auto& p = *prior_;
  const int m = static_cast<int>(p.r.size());
  Eigen::VectorXd dx(p.tangentDimension());
  int off = 0;
  for (std::size_t i = 0; i < p.blocks.size(); ++i) {
    dx.segment(off, p.blocks[i].tangent_size) = blockDifference(p.blocks[i], parameters[i]);
    off += p.blocks[i].tangent_size;
  }
  Eigen::Map<Eigen::VectorXd>(residuals, m) = p.r + p.J * dx;
  if (jacobians == nullptr) return true;
  off = 0;
  for (std::size_t i = 0; i < p.blocks.size(); ++i) {
    const auto& b = p.blocks[i];
    if (jacobians[i] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Jg(jacobians[i], m, b.size);
      if (b.kind == BlockKind::kPose) {
        const Eigen::Map<const Eigen::Quaterniond> q(parameters[i] + 3);
        Jg.leftCols(3) = p.J.middleCols(off, 3);
        Jg.rightCols(4) = p.J.middleCols(off + 3, 3) * PoseManifold::liftQuaternionJacobian(q);
      } else {
        Jg = p.J.middleCols(off, b.size);
      }
    }
    off += b.tangent_size;
  }
  return true;
}

}  // namespace mcvio::estimator
