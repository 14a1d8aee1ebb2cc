#include "mcvio/estimator/model_agreement_stop.hpp"

#include <cmath>

namespace mcvio::estimator {

ceres::CallbackReturnType ModelAgreementStop::operator()(const ceres::IterationSummary& summary) {
  // Iteration 0 only evaluates the start; rejected steps say nothing about the minimum.
  if (summary.iteration == 0 || !summary.step_is_successful || !(summary.relative_decrease > 0.0))
    return ceres::SOLVER_CONTINUE;
  // relative_decrease = actual / predicted decrease of this step.
  const double predicted = summary.cost_change / summary.relative_decrease;
  const double mismatch = std::abs(summary.cost_change - predicted);
  return mismatch <= tolerance_ * summary.cost ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
}

}  // namespace mcvio::estimator
