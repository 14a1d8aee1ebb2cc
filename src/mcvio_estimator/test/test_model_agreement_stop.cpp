#include <gtest/gtest.h>

#include <cmath>

#include <ceres/ceres.h>

#include "mcvio/estimator/model_agreement_stop.hpp"

using mcvio::estimator::ModelAgreementStop;

namespace {

// r = (x0 + 2 x1 - 3, x0 - x1 - 1): linear, so the Gauss-Newton model is exact.
struct LinearResidual {
  template <typename T>
  bool operator()(const T* x, T* r) const {
    r[0] = x[0] + T(2) * x[1] - T(3);
    r[1] = x[0] - x[1] - T(1);
    return true;
  }
};

// Rosenbrock's residuals: far from quadratic away from the minimum at (1, 1).
struct RosenbrockResidual {
  template <typename T>
  bool operator()(const T* x, T* r) const {
    r[0] = T(10) * (x[1] - x[0] * x[0]);
    r[1] = T(1) - x[0];
    return true;
  }
};

template <typename Residual>
ceres::Solver::Summary solve(double* x, bool with_stop) {
  ceres::Problem problem;
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Residual, 2, 2>(new Residual), nullptr, x);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.function_tolerance = 1e-6;
  options.max_num_iterations = 50;
  options.jacobi_scaling = false;  // as in the estimator
  ModelAgreementStop stop(options.function_tolerance);
  if (with_stop) options.callbacks.push_back(&stop);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary;
}

}  // namespace

TEST(ModelAgreementStop, LinearProblemStopsAfterOneSolve) {
  double with[2] = {10.0, -7.0};
  double without[2] = {10.0, -7.0};
  const auto a = solve<LinearResidual>(with, true);
  const auto b = solve<LinearResidual>(without, false);
  EXPECT_EQ(a.termination_type, ceres::USER_SUCCESS);
  EXPECT_EQ(a.num_linear_solves, 1);
  // Ceres' own test solves again (and again after LM's slightly damped first step) only to find the
  // next step tiny.
  EXPECT_GE(b.num_linear_solves, 2);
  // The minimum is (5/3, 2/3). One step of LM (damping 1e-4 of the diagonal at the default trust
  // region) removes all but about 1e-4 of the initial error.
  const double initial_error = std::hypot(10.0 - 5.0 / 3.0, -7.0 - 2.0 / 3.0);
  const double error = std::hypot(with[0] - 5.0 / 3.0, with[1] - 2.0 / 3.0);
  EXPECT_LT(error, 1e-3 * initial_error);
  EXPECT_LT(a.final_cost, 1e-6 * a.initial_cost);
}

TEST(ModelAgreementStop, NonlinearProblemKeepsIterating) {
  double x[2] = {-1.2, 1.0};
  const auto s = solve<RosenbrockResidual>(x, true);
  // The first steps disagree with their model: the solve goes on until it reaches the minimum.
  EXPECT_GT(s.num_successful_steps, 2);
  EXPECT_NEAR(x[0], 1.0, 1e-4);
  EXPECT_NEAR(x[1], 1.0, 1e-4);
}

TEST(ModelAgreementStop, IgnoresIterationZeroAndRejectedSteps) {
  ModelAgreementStop stop(1e-3);
  ceres::IterationSummary s;
  s.iteration = 0;
  s.step_is_successful = true;
  s.cost = 1.0;
  EXPECT_EQ(stop(s), ceres::SOLVER_CONTINUE);
  s.iteration = 3;
  s.step_is_successful = false;
  s.cost_change = 0.5;
  s.relative_decrease = 1.0;
  EXPECT_EQ(stop(s), ceres::SOLVER_CONTINUE);
  s.step_is_successful = true;
  EXPECT_EQ(stop(s), ceres::SOLVER_TERMINATE_SUCCESSFULLY);
  // Actual decrease 0.5 against a predicted 1.0: the model was off by half the cost.
  s.relative_decrease = 0.5;
  EXPECT_EQ(stop(s), ceres::SOLVER_CONTINUE);
}
