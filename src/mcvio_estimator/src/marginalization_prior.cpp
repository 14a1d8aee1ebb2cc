#include "mcvio/estimator/marginalization_prior.hpp"

#include <Eigen/Geometry>

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
