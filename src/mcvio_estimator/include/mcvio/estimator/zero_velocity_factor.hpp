#pragma once
#include <ceres/sized_cost_function.h>

namespace mcvio::estimator {

/// Zero-velocity update for a frame detected at rest: residual v / sigma on the speed-bias block
/// [v, bg, ba] (9). Keeps a resting device from drifting.
class ZeroVelocityFactor : public ceres::SizedCostFunction<3, 9> {
 public:
  explicit ZeroVelocityFactor(double sigma_mps) : inv_sigma_(1.0 / sigma_mps) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    for (int i = 0; i < 3; ++i) residuals[i] = inv_sigma_ * parameters[0][i];
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      for (int i = 0; i < 27; ++i) jacobians[0][i] = 0.0;
      for (int i = 0; i < 3; ++i) jacobians[0][i * 9 + i] = inv_sigma_;
    }
    return true;
  }

 private:
  double inv_sigma_;
};

}  // namespace mcvio::estimator
