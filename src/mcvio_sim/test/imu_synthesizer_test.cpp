#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "mcvio/sim/frame_riding_trajectory.hpp"
#include "mcvio/sim/imu_synthesizer.hpp"
#include "mcvio/sim/sinusoid_trajectory.hpp"

namespace mcvio::sim {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;

struct NavState {
  Quaterniond q;
  Vector3d v, p;
};

struct NavRate {
  Eigen::Vector4d dq;
  Vector3d dv, dp;
};

NavRate rate(const NavState& s, const ImuSample& m) {
  const Quaterniond w(0, m.gyro.x(), m.gyro.y(), m.gyro.z());
  const Quaterniond qd = s.q * w;
  NavRate r;
  r.dq = 0.5 * qd.coeffs();
  r.dv = s.q * m.accel + kGravityW;
  r.dp = s.v;
  return r;
}

NavState advance(const NavState& s, const NavRate& r, double h) {
  NavState o;
  o.q.coeffs() = s.q.coeffs() + h * r.dq;
  o.v = s.v + h * r.dv;
  o.p = s.p + h * r.dp;
  return o;
}

/// RK4 over pairs of IMU intervals: the middle sample is the midpoint measurement.
double integrationError(const Trajectory& traj, const ImuSequence& seq) {
  const auto& m = seq.samples;
  NavState s{seq.ground_truth[0].q_WB, seq.ground_truth[0].v_WB, seq.ground_truth[0].p_WB};
  double worst = 0;
  for (size_t k = 0; k + 2 < m.size(); k += 2) {
    const double h = toSeconds(m[k + 2].t - m[k].t);
    const NavRate k1 = rate(s, m[k]);
    const NavRate k2 = rate(advance(s, k1, h / 2), m[k + 1]);
    const NavRate k3 = rate(advance(s, k2, h / 2), m[k + 1]);
    const NavRate k4 = rate(advance(s, k3, h), m[k + 2]);
    s.q.coeffs() += h / 6 * (k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq);
    s.q.normalize();
    s.v += h / 6 * (k1.dv + 2 * k2.dv + 2 * k3.dv + k4.dv);
    s.p += h / 6 * (k1.dp + 2 * k2.dp + 2 * k3.dp + k4.dp);
    worst = std::max(worst, (s.p - traj.evaluate(m[k + 2].t).p_wb).norm());
  }
  return worst;
}

ImuSynthesizer::Options exactImu() {
  ImuSynthesizer::Options o;
  o.add_noise = false;
  return o;
}

TEST(ImuSynthesizer, NoiseFreeImuIntegratesBackToTheTrajectory) {
  const Timestamp start = 1000000000, end = start + fromSeconds(60.0);
  SinusoidTrajectory traj(SinusoidTrajectory::Options::loop({0, 0, 1.5}, {3, 2.2, 0.35}, 26.0), start, end);
  const ImuSequence seq = ImuSynthesizer(exactImu()).synthesize(traj, start, end);
  ASSERT_EQ(seq.samples.size(), 12001u);
  EXPECT_LT(integrationError(traj, seq), 1e-3);
}

TEST(ImuSynthesizer, ElevatorRideIsFeltByTheImu) {
  const Timestamp start = 0, end = fromSeconds(60.0);
  auto local = std::make_shared<SinusoidTrajectory>(
      SinusoidTrajectory::Options::handHeld({0, 0, 1.4}, {0.3, 0.3, 0.12}, 0.12), start, end);
  const RideProfile ride(fromSeconds(20), fromSeconds(15), Vector3d::UnitZ(), 12.0);
  FrameRidingTrajectory traj(local, ride);
  const ImuSequence seq = ImuSynthesizer(exactImu()).synthesize(traj, start, end);
  EXPECT_LT(integrationError(traj, seq), 1e-3);
  // Integrating only the in-cabin motion's IMU misses the 12 m ride.
  const ImuSequence cabin_only = ImuSynthesizer(exactImu()).synthesize(*local, start, end);
  const Vector3d dz = traj.evaluate(end).p_wb - local->evaluate(end).p_wb;
  EXPECT_NEAR(dz.z(), 12.0, 1e-9);
  EXPECT_GT((seq.samples[5000].accel - cabin_only.samples[5000].accel).norm(), 0.1);
}

TEST(ImuSynthesizer, NoiseMatchesTheDensitiesAndIsSeeded) {
  const Timestamp start = 0, end = fromSeconds(50.0);
  SinusoidTrajectory traj(SinusoidTrajectory::Options::loop({0, 0, 1.5}, {3, 2.2, 0.35}, 26.0), start, end);
  ImuSynthesizer::Options noisy;
  noisy.seed = 3;
  const ImuSequence a = ImuSynthesizer(noisy).synthesize(traj, start, end);
  const ImuSequence b = ImuSynthesizer(noisy).synthesize(traj, start, end);
  const ImuSequence exact = ImuSynthesizer(exactImu()).synthesize(traj, start, end);
  double sum2 = 0;
  size_t n = 0;
  for (size_t k = 0; k < a.samples.size(); ++k) {
    EXPECT_EQ(a.samples[k].gyro, b.samples[k].gyro);
    const Vector3d e = a.samples[k].gyro - exact.samples[k].gyro - a.ground_truth[k].bias_gyro;
    sum2 += e.squaredNorm();
    n += 3;
  }
  const double expected = noisy.noise.gyroscope_noise_density * std::sqrt(noisy.noise.rate_hz);
  EXPECT_NEAR(std::sqrt(sum2 / n), expected, 0.03 * expected);
  // The accelerometer bias wanders like a random walk: after 50 s its spread is ~ rw * sqrt(T).
  EXPECT_GT(a.ground_truth.back().bias_accel.norm(), 1e-4);
  noisy.seed = 4;
  const ImuSequence c = ImuSynthesizer(noisy).synthesize(traj, start, end);
  EXPECT_NE(a.samples[10].gyro, c.samples[10].gyro);
}

TEST(SinusoidTrajectory, StaysInsideItsExcursionAndMatchesFiniteDifferences) {
  SinusoidTrajectory traj(SinusoidTrajectory::Options::loop({1, 2, 1.5}, {3, 2.2, 0.35}, 26.0), 0,
                          fromSeconds(60));
  const Vector3d bound = traj.maxExcursion();
  EXPECT_NEAR(bound.x(), 3.0, 1e-12);
  for (Timestamp t = 0; t <= fromSeconds(60); t += fromSeconds(0.37)) {
    const KinematicState s = traj.evaluate(t);
    EXPECT_TRUE(((s.p_wb - Vector3d(1, 2, 1.5)).cwiseAbs().array() <= bound.array() + 1e-12).all());
    const Timestamp h = 1000000;  // 1 ms central differences
    const KinematicState a = traj.evaluate(t - h), b = traj.evaluate(t + h);
    EXPECT_LT((s.v_w - (b.p_wb - a.p_wb) / 2e-3).norm(), 1e-4);
    EXPECT_LT((s.a_w - (b.v_w - a.v_w) / 2e-3).norm(), 1e-4);
    const Eigen::AngleAxisd d(a.q_wb.conjugate() * b.q_wb);
    EXPECT_LT((s.omega_b - d.axis() * d.angle() / 2e-3).norm(), 1e-4);
  }
}

}  // namespace
}  // namespace mcvio::sim
