#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "mcvio/estimator/imu_preintegrator.hpp"
#include "mcvio/estimator/so3.hpp"

namespace mcvio::estimator {
namespace {

constexpr Timestamp kStep = 5'000'000;  // 200 Hz

std::vector<ImuSample> varyingSamples(int n) {
  std::vector<ImuSample> out;
  for (int k = 0; k < n; ++k) {
    const double t = k * 0.005;
    ImuSample s;
    s.t = 1'000'000'000 + k * kStep;
    s.gyro = Eigen::Vector3d(0.3 * std::sin(3 * t) + 0.1, -0.5 * std::cos(2 * t), 0.8 * std::sin(t) + 0.2);
    s.accel = Eigen::Vector3d(1.0 + std::sin(5 * t), -0.7 * std::cos(4 * t), 9.81 + 0.5 * std::sin(2 * t));
    out.push_back(s);
  }
  return out;
}

ImuPreintegrator integrateAll(const std::vector<ImuSample>& samples, const ImuBias& b) {
  ImuPreintegrator pre(b, ImuNoiseParams{});
  for (const auto& s : samples) pre.integrate(s);
  return pre;
}

TEST(ImuPreintegrator, BiasJacobiansMatchNumericalDifferentiation) {
  const auto samples = varyingSamples(41);
  ImuBias b;
  b.gyro = Eigen::Vector3d(0.01, -0.02, 0.015);
  b.accel = Eigen::Vector3d(0.1, 0.05, -0.08);
  const ImuPreintegrator pre = integrateAll(samples, b);
  const double eps = 1e-6;
  for (int k = 0; k < 6; ++k) {
    ImuBias bp = b, bm = b;
    if (k < 3) {
      bp.gyro[k] += eps;
      bm.gyro[k] -= eps;
    } else {
      bp.accel[k - 3] += eps;
      bm.accel[k - 3] -= eps;
    }
    const ImuPreintegrator pp = integrateAll(samples, bp);
    const ImuPreintegrator pm = integrateAll(samples, bm);
    const Eigen::Vector3d num_r = so3::logQuat(pm.deltaQ().conjugate() * pp.deltaQ()) / (2 * eps);
    const Eigen::Vector3d num_v = (pp.deltaV() - pm.deltaV()) / (2 * eps);
    const Eigen::Vector3d num_p = (pp.deltaP() - pm.deltaP()) / (2 * eps);
    if (k < 3) {
      EXPECT_LT((num_r - pre.dR_dbg().col(k)).norm(), 1e-6) << "dR/dbg col " << k;
      EXPECT_LT((num_v - pre.dV_dbg().col(k)).norm(), 1e-6) << "dV/dbg col " << k;
      EXPECT_LT((num_p - pre.dP_dbg().col(k)).norm(), 1e-6) << "dP/dbg col " << k;
    } else {
      EXPECT_LT(num_r.norm(), 1e-6) << "dR/dba must be zero";
      EXPECT_LT((num_v - pre.dV_dba().col(k - 3)).norm(), 1e-6) << "dV/dba col " << k - 3;
      EXPECT_LT((num_p - pre.dP_dba().col(k - 3)).norm(), 1e-6) << "dP/dba col " << k - 3;
    }
  }
  // The Jacobians must not be trivially zero for this motion.
  EXPECT_GT(pre.dR_dbg().norm(), 0.1);
  EXPECT_GT(pre.dV_dbg().norm(), 1e-3);
  EXPECT_GT(pre.dP_dba().norm(), 1e-3);
}

// Constant body rate and constant world acceleration: midpoint integration is exact here, so the
// residual against the analytic states must vanish.
TEST(ImuPreintegrator, ResidualZeroOnExactData) {
  const Eigen::Vector3d gravity(0, 0, -9.81);
  const Eigen::Vector3d w(0.2, -0.3, 0.5), a_w(0.4, -0.2, 0.3);
  const Eigen::Vector3d p0(1, 2, 3), v0(0.5, -0.1, 0.2);
  const Eigen::Quaterniond q0 = so3::expQuat(Eigen::Vector3d(0.1, 0.2, -0.3));
  ImuBias b;
  b.gyro = Eigen::Vector3d(0.01, 0.02, -0.01);
  b.accel = Eigen::Vector3d(-0.05, 0.1, 0.02);
  ImuPreintegrator pre(b, ImuNoiseParams{});
  const int n = 21;
  for (int k = 0; k < n; ++k) {
    const double t = k * 0.005;
    const Eigen::Quaterniond q = q0 * so3::expQuat(w * t);
    ImuSample s;
    s.t = k * kStep;
    s.gyro = w + b.gyro;
    s.accel = q.conjugate() * (a_w - gravity) + b.accel;
    pre.integrate(s);
  }
  const double T = 0.1;
  const Eigen::Quaterniond q1 = q0 * so3::expQuat(w * T);
  const Eigen::Vector3d v1 = v0 + a_w * T, p1 = p0 + v0 * T + 0.5 * a_w * T * T;
  EXPECT_NEAR(pre.deltaTime(), T, 1e-12);
  const auto r = pre.residual(p0, q0, v0, b, p1, q1, v1, b, gravity);
  EXPECT_LT(r.norm(), 1e-9) << r.transpose();

  // A wrong state must give a residual (the test can fail).
  const auto r_bad = pre.residual(p0, q0, v0, b, p1 + Eigen::Vector3d(0.01, 0, 0), q1, v1, b, gravity);
  EXPECT_GT(r_bad.norm(), 1e-3);

  // First-order bias correction: linearised at a slightly wrong bias, the corrected residual at the
  // true bias is second-order small; after repropagation it is zero again.
  ImuBias b_off = b;
  b_off.gyro += Eigen::Vector3d(1e-3, -1e-3, 2e-3);
  b_off.accel += Eigen::Vector3d(1e-2, 5e-3, -1e-2);
  ImuPreintegrator pre_off(b_off, ImuNoiseParams{});
  for (const auto& s : pre.samples()) pre_off.integrate(s);
  const auto r_uncorrected_ref = pre_off.residual(p0, q0, v0, b_off, p1, q1, v1, b_off, gravity);
  const auto r_corrected = pre_off.residual(p0, q0, v0, b, p1, q1, v1, b, gravity);
  EXPECT_LT(r_corrected.norm(), 1e-6);
  EXPECT_GT(r_uncorrected_ref.norm(), 1e-4);
  EXPECT_TRUE(pre_off.needsRepropagation(b, 1e-4, 1e-3));
  pre_off.repropagate(b);
  EXPECT_LT(pre_off.residual(p0, q0, v0, b, p1, q1, v1, b, gravity).norm(), 1e-9);
}

TEST(ImuPreintegrator, CovarianceIsSymmetricPositiveAndGrows) {
  const auto samples = varyingSamples(101);
  ImuNoiseParams noise;
  ImuPreintegrator pre(ImuBias{}, noise);
  double last_trace = 0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    pre.integrate(samples[k]);
    if (k == 0) continue;
    const auto& P = pre.covariance();
    EXPECT_LT((P - P.transpose()).norm(), 1e-15 + 1e-12 * P.norm());
    EXPECT_GT(P.trace(), last_trace);
    last_trace = P.trace();
  }
  Eigen::SelfAdjointEigenSolver<ImuPreintegrator::Matrix15> es(pre.covariance());
  EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
  const double T = pre.deltaTime();
  // Bias blocks are pure random walks; the rotation block is ~ sigma_g^2 T for slow rotation.
  EXPECT_NEAR(pre.covariance()(9, 9), noise.gyroscope_random_walk * noise.gyroscope_random_walk * T, 1e-15);
  EXPECT_NEAR(pre.covariance()(12, 12), noise.accelerometer_random_walk * noise.accelerometer_random_walk * T,
              1e-12);
  const double sg2T = noise.gyroscope_noise_density * noise.gyroscope_noise_density * T;
  const double rot_var = pre.covariance().block<3, 3>(0, 0).trace() / 3.0;
  EXPECT_NEAR(rot_var, sg2T, 0.1 * sg2T);
  // S^T S must invert the covariance.
  const auto S = pre.sqrtInformation();
  const ImuPreintegrator::Matrix15 I = S.transpose() * S * pre.covariance();
  EXPECT_LT((I - ImuPreintegrator::Matrix15::Identity()).norm(), 1e-6);
}

// Monte Carlo: the propagated covariance of [dtheta, dv, dp] matches the spread of the deltas
// integrated from noisy samples (white noise with the discrete sigma of the densities).
TEST(ImuPreintegrator, CovarianceMatchesMonteCarlo) {
  const auto clean = varyingSamples(41);
  ImuNoiseParams noise;
  noise.gyroscope_random_walk = 0;
  noise.accelerometer_random_walk = 0;
  const ImuPreintegrator ref = integrateAll(clean, ImuBias{});
  ImuPreintegrator model(ImuBias{}, noise);
  for (const auto& s : clean) model.integrate(s);
  const double dt = 0.005;
  const double sg = noise.gyroscope_noise_density / std::sqrt(dt);
  const double sa = noise.accelerometer_noise_density / std::sqrt(dt);
  std::mt19937 rng(42);
  std::normal_distribution<double> nd;
  const int runs = 2000;
  Eigen::Matrix<double, 9, 9> emp = Eigen::Matrix<double, 9, 9>::Zero();
  for (int r = 0; r < runs; ++r) {
    ImuPreintegrator pre(ImuBias{}, noise);
    for (auto s : clean) {
      s.gyro += sg * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
      s.accel += sa * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
      pre.integrate(s);
    }
    Eigen::Matrix<double, 9, 1> e;
    e.segment<3>(0) = so3::logQuat(ref.deltaQ().conjugate() * pre.deltaQ());
    e.segment<3>(3) = pre.deltaV() - ref.deltaV();
    e.segment<3>(6) = pre.deltaP() - ref.deltaP();
    emp += e * e.transpose() / runs;
  }
  for (int i = 0; i < 9; ++i) {
    const double predicted = model.covariance()(i, i);
    EXPECT_NEAR(emp(i, i) / predicted, 1.0, 0.25) << "diagonal " << i;
  }
}

TEST(ImuPreintegrator, IgnoresSamplesThatDoNotAdvanceTime) {
  const auto samples = varyingSamples(5);
  ImuPreintegrator pre(ImuBias{}, ImuNoiseParams{});
  pre.integrate(samples[0]);
  pre.integrate(samples[1]);
  pre.integrate(samples[1]);
  pre.integrate(samples[0]);
  pre.integrate(samples[2]);
  EXPECT_EQ(pre.sampleCount(), 3u);
  EXPECT_EQ(pre.rejectedSamples(), 2u);
  EXPECT_NEAR(pre.deltaTime(), 0.01, 1e-12);
}

}  // namespace
}  // namespace mcvio::estimator
