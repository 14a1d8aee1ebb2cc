#pragma once
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <ceres/cost_function.h>

namespace mcvio::estimator {

/// How a parameter block lives on its manifold.
enum class BlockKind {
  kEuclidean,  ///< any vector (speed-bias, ...); tangent = ambient
  kPose,       ///< [p, q] with PoseManifold (7 ambient, 6 tangent)
  kLandmark,   ///< small Euclidean landmark block; Schur-eliminated first (no two in one residual)
};

/// A linear Gaussian prior left by marginalisation: cost 0.5 |r + J (x - x_lin)|^2 over the kept
/// blocks, with x - x_lin taken in each block's tangent space. J is the square-root information
/// (J^T J = Schur complement), r the residual at x_lin. The kept blocks stay linearised at x_lin
/// (first-estimate Jacobians) so the prior never adds information along unobservable directions.
struct MarginalizationPrior {
  struct Block {
    double* data = nullptr;  ///< the estimator's storage of this block
    BlockKind kind = BlockKind::kEuclidean;
    int size = 0;          ///< ambient size
    int tangent_size = 0;  ///< columns in J
    std::vector<double> x_lin;
  };
  std::vector<Block> blocks;
  Eigen::MatrixXd J;
  Eigen::VectorXd r;

  int tangentDimension() const;
  bool involves(const double* data) const;
  /// r + J dx at the blocks' current values.
  Eigen::VectorXd evaluate() const;
  /// Information matrix J^T J over the blocks (tangent order of `blocks`).
  Eigen::MatrixXd information() const { return J.transpose() * J; }
  /// Replaces what the prior knows about the common translation of its pose blocks (where the
  /// window is, as against its shape) by `covariance` [m^2], at the last pose block's position:
  /// after a correction that moved the whole window, whose own error is now all that is known of
  /// where it is. What the prior knows of everything a common translation leaves unchanged (the
  /// positions relative to each other, attitudes, velocities, biases) stays exactly as it was.
  void setCommonTranslationCovariance(const Eigen::Matrix3d& covariance);
};

/// Ceres factor for a MarginalizationPrior (one residual block over all its blocks).
class MarginalizationFactor : public ceres::CostFunction {
 public:
  explicit MarginalizationFactor(std::shared_ptr<const MarginalizationPrior> prior);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  /// Parameter pointers in the order the factor expects them.
  std::vector<double*> parameterBlocks() const;

 private:
  std::shared_ptr<const MarginalizationPrior> prior_;
};

}  // namespace mcvio::estimator
