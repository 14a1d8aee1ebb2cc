#pragma once
#include <ceres/iteration_callback.h>

namespace mcvio::estimator {

/// Ends a Ceres solve once an accepted step did what the linearised model predicted.
///
/// Ceres' own function-tolerance test judges the step *after* the last one: it solves the linear
/// system again and evaluates the cost once more only to learn that the next step would be tiny,
/// then discards it. In a sliding window started from the IMU prediction the first Gauss-Newton
/// step nearly always lands on the minimum, so that test doubled the linear solves per frame.
/// Here the solve stops right after an accepted step when the actual cost decrease differs from the
/// model's predicted decrease by at most `tolerance` times the cost: the cost is then locally
/// quadratic along the step, and another step would gain about that mismatch at most. Damped steps
/// on an ill-conditioned problem (a window just initialised) also match their model while still far
/// from the minimum: the estimator leaves this out there.
class ModelAgreementStop : public ceres::IterationCallback {
 public:
  explicit ModelAgreementStop(double tolerance) : tolerance_(tolerance) {}

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override;

 private:
  double tolerance_;
};

}  // namespace mcvio::estimator
