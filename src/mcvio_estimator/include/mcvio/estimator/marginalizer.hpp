#pragma once
#include <memory>
#include <set>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include "mcvio/estimator/marginalization_prior.hpp"

namespace mcvio::estimator {

/// Linearises a set of residual blocks at the current parameter values and reduces the normal
/// equations by Schur complement. Used for marginalisation (removed states -> prior on the kept
/// ones) and for the marginal covariance of one block. Landmark blocks are eliminated first, one
/// at a time, which is exact because no residual touches two landmarks.
/// Robust losses are applied by scaling residual and Jacobian with sqrt(rho'), as in IRLS.
class Marginalizer {
 public:
  /// Registers a parameter block (must be done for every block a residual uses).
  void addParameterBlock(double* data, BlockKind kind, int size);
  /// Adds a residual block. The cost function and loss must outlive the calls below; the
  /// Marginalizer does not take ownership.
  void addResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                        double* const* parameters, int num_parameters);
  void addResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                        const std::vector<double*>& parameters) {
    addResidualBlock(cost, loss, parameters.data(), static_cast<int>(parameters.size()));
  }

  /// Schur-complements the `drop` blocks out of all added residuals. The prior covers every other
  /// block touched by the residuals, linearised at its current value. Returns nullptr when nothing
  /// is left to keep. Throws std::logic_error if a residual couldn't be evaluated.
  std::shared_ptr<MarginalizationPrior> marginalize(const std::set<const double*>& drop) const;

  /// The two results of a marginalisation. `prior` is what marginalize() returns: the directions
  /// known to at least 1e-8 of the strongest, for the optimisation. `whole` is all of the Schur
  /// complement's information (J only, r = 0; Jacobi-scaled floor 1e-13 of each variable's own
  /// information), for the covariance, which uses it in place of `prior`.
  struct SplitPrior {
    std::shared_ptr<MarginalizationPrior> prior;
    std::shared_ptr<MarginalizationPrior> whole;  ///< nullptr from marginalize()
  };
  /// As marginalize(), and also the whole information. `whole_in` is the whole information of the
  /// previous marginalisation and `prior_in` the residual (among the added ones) of the prior that
  /// came with it: in the whole system `whole_in` replaces `prior_in`. Both null: the added
  /// residuals are the whole information. The optimisation's prior stays exactly what marginalize()
  /// gives.
  SplitPrior marginalizeSplit(const std::set<const double*>& drop, const MarginalizationPrior* whole_in,
                              const ceres::CostFunction* prior_in) const;

  /// Marginal covariance (tangent space) of `block` given all added residuals, with every other
  /// block marginalised. False if the information matrix is not positive definite.
  bool marginalCovariance(const double* block, Eigen::MatrixXd* covariance) const;
  /// Joint marginal covariance of `blocks`, in their order (tangent spaces stacked).
  bool marginalCovariance(const std::vector<const double*>& blocks, Eigen::MatrixXd* covariance) const;

  /// Information (Hessian) of all non-landmark blocks with the landmarks in `drop` eliminated, in
  /// the given block order (tangent dims). Exposed for tests.
  void reducedSystem(const std::vector<const double*>& order, const std::set<const double*>& drop,
                     Eigen::MatrixXd* H, Eigen::VectorXd* g) const;

  std::size_t residualCount() const { return residuals_.size(); }

 private:
  struct BlockInfo {
    double* data;
    BlockKind kind;
    int size;
    int tangent_size;
  };
  /// Parameters `first .. first + count` of params_ / block_ids_.
  struct Residual {
    const ceres::CostFunction* cost;
    const ceres::LossFunction* loss;
    int first;
    int count;
  };
  int blockId(const double* data) const;
  SplitPrior marginalizeImpl(const std::set<const double*>& drop, const MarginalizationPrior* whole_in,
                             const ceres::CostFunction* prior_in, bool want_whole) const;
  /// Per-block flags of a pointer set (pointers that are not registered blocks are ignored).
  std::vector<char> blockFlags(const std::set<const double*>& blocks) const;
  /// reducedSystem() over block ids: `order` lists the dense blocks, `dropped` flags the blocks of
  /// `drop`.
  void reduce(const std::vector<int>& order, const std::vector<char>& dropped, Eigen::MatrixXd* H,
              Eigen::VectorXd* g) const;
  /// Residual and tangent-space Jacobians (loss applied).
  bool linearize(const Residual& res, Eigen::VectorXd* r, std::vector<Eigen::MatrixXd>* J) const;

  // Blocks are addressed by a small id so the per-residual work indexes vectors, not hash maps.
  std::vector<BlockInfo> blocks_;
  std::unordered_map<const double*, int> block_ids_by_data_;
  std::vector<Residual> residuals_;
  std::vector<double*> params_;
  std::vector<int> block_ids_;
};

}  // namespace mcvio::estimator
