// Unit tests of ConflictIntervalSmoother (the conflict window) on a constructed ride: exact IMU
// samples of a known motion, measured with an accelerometer bias the held estimate does not know.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "mcvio/estimator/conflict_interval_smoother.hpp"
#include "mcvio/estimator/so3.hpp"

using namespace mcvio;
using estimator::ConflictIntervalSmoother;
using estimator::ImuBias;
using estimator::ImuBuffer;

namespace {

constexpr Timestamp kStart = 1'000'000'000;
constexpr Timestamp kFramePeriod = 50'000'000;  // 20 Hz
constexpr Timestamp kImuPeriod = 5'000'000;     // 200 Hz
const Eigen::Vector3d kGravity(0, 0, -9.81);
const Eigen::Vector3d kTrueAccelBias(0.03, -0.02, 0.01);

// EIGEN_PI is a long double: spelled as a double so the vectors need no narrowing.
constexpr double kPi = EIGEN_PI;

/// No rotation; constant walk along x plus a 10 s cycloid ride of 8 m along z from 1 s.
struct Motion {
  static constexpr double kRideStart = 1.0, kRideDuration = 10.0, kRideTravel = 8.0;
  static Eigen::Vector3d accel(double s) {
    const double u = (s - kRideStart) / kRideDuration;
    if (u <= 0 || u >= 1) return Eigen::Vector3d::Zero();
    return {0, 0, kRideTravel / (kRideDuration * kRideDuration) * 2 * kPi * std::sin(2 * kPi * u)};
  }
  static Eigen::Vector3d velocity(double s) {
    const double u = std::clamp((s - kRideStart) / kRideDuration, 0.0, 1.0);
    return {0.4, 0, kRideTravel / kRideDuration * (1 - std::cos(2 * kPi * u)) * (u > 0 && u < 1 ? 1 : 0)};
  }
  static Eigen::Vector3d position(double s) {
    const double u = std::clamp((s - kRideStart) / kRideDuration, 0.0, 1.0);
    return {0.4 * s, 0, kRideTravel * (u - std::sin(2 * kPi * u) / (2 * kPi))};
  }
};

double seconds(Timestamp t) { return toSeconds(t - kStart); }

/// The accelerometer's bias at a time [s]: constant, or walking away from the held estimate.
using BiasProfile = Eigen::Vector3d (*)(double);
Eigen::Vector3d constantBias(double) { return kTrueAccelBias; }
/// Grows from 0 (the held estimate, right when the window opens) at a constant rate.
Eigen::Vector3d walkingBias(double s) { return kTrueAccelBias * (s / 10.0); }

ImuBuffer imuFor(double duration_s, BiasProfile bias = constantBias) {
  ImuBuffer imu;
  for (Timestamp t = kStart; seconds(t) <= duration_s + 1e-9; t += kImuPeriod) {
    ImuSample s;
    s.t = t;
    s.accel = Motion::accel(seconds(t)) - kGravity + bias(seconds(t));  // body = world orientation
    EXPECT_EQ(imu.add(s, 0.1), ImuBuffer::AddResult::kAccepted);
  }
  return imu;
}

/// An IMU whose bias does not walk: the correction's best shape is a constant.
ImuNoiseParams steadyBiasImu() {
  ImuNoiseParams n;
  n.accelerometer_random_walk = 0;
  return n;
}

ConflictIntervalSmoother::Options options() {
  ConflictIntervalSmoother::Options o;
  o.settle_frames = 20;
  o.max_acceleration_correction = 0.2;
  return o;
}

/// Opens the window at kStart with the true state and the held bias 0, adds frames up to
/// interval_s (then the exit) and 20 more.
Timestamp fillWindow(ConflictIntervalSmoother* s, double interval_s) {
  s->begin(kStart, Motion::position(0), Eigen::Quaterniond::Identity(), Motion::velocity(0), ImuBias{});
  Timestamp t = kStart;
  for (t = kStart + kFramePeriod; seconds(t) <= interval_s + 1e-9; t += kFramePeriod) {
    EXPECT_FALSE(s->ready());
    s->addFrame(t, Eigen::Quaterniond::Identity());
  }
  s->markExit();
  for (int i = 0; i < 20; ++i, t += kFramePeriod) {
    EXPECT_FALSE(s->ready());
    s->addFrame(t, Eigen::Quaterniond::Identity());
  }
  EXPECT_TRUE(s->ready());
  return t - kFramePeriod;
}

std::vector<ConflictIntervalSmoother::SettledVelocity> trueVelocities(Timestamp last, int n) {
  std::vector<ConflictIntervalSmoother::SettledVelocity> v;
  for (int i = n - 1; i >= 0; --i) {
    const Timestamp t = last - i * kFramePeriod;
    v.push_back({t, Motion::velocity(seconds(t))});
  }
  return v;
}

}  // namespace

TEST(ConflictIntervalSmoother, RecoversTheAccelerationErrorAndThePositions) {
  ConflictIntervalSmoother s(options());
  const Timestamp last = fillWindow(&s, 12.0);
  const ImuBuffer imu = imuFor(seconds(last) + 0.1);
  // The live estimate drifted: wherever it is, the shift brings it onto the corrected position.
  const Eigen::Vector3d p_end = Motion::position(seconds(last)) + Eigen::Vector3d(1.5, -2.0, 0.7);
  const auto res = s.finish(imu, steadyBiasImu(), kGravity, p_end, trueVelocities(last, 10));
  ASSERT_TRUE(res.applied) << res.message;
  EXPECT_FALSE(s.active());
  // The body frame is the world's here: the correction removes the unknown bias.
  EXPECT_LT((res.acceleration_correction + kTrueAccelBias).norm(), 1e-4) << res.acceleration_correction.transpose();
  ASSERT_EQ(res.revisions.size(), 260u);  // 240 frames of the interval, 20 settling
  double worst = 0;
  for (const auto& r : res.revisions) worst = std::max(worst, (r.p_WB - Motion::position(seconds(r.t))).norm());
  EXPECT_LT(worst, 1e-3) << "worst corrected position error [m]";
  EXPECT_LT((res.shift - Eigen::Vector3d(-1.5, 2.0, -0.7)).norm(), 1e-3) << res.shift.transpose();
  // Without the correction the held bias would have left the end 0.5 * |b| * T^2 = 2.9 m off.
  EXPECT_NE(res.message.find("smoothed"), std::string::npos) << res.message;
}

TEST(ConflictIntervalSmoother, ShapesTheCorrectionForABiasThatWalks) {
  // The held bias was right when the window opened, and the true one drifted away from it over
  // the 12 s interval (as the accelerometer's random walk does): the velocity error at the end is
  // the integral of the drift, the position error its double integral. A constant correction
  // that matches the end velocity over-corrects the positions; the shaped one follows the growth.
  const auto worstError = [](double held_sigma, Eigen::Vector3d* end_error) {
    ConflictIntervalSmoother::Options o = options();
    o.held_acceleration_sigma = held_sigma;
    ConflictIntervalSmoother s(o);
    const Timestamp last = fillWindow(&s, 12.0);
    const auto res = s.finish(imuFor(seconds(last) + 0.1, walkingBias), ImuNoiseParams{}, kGravity,
                              Motion::position(seconds(last)), trueVelocities(last, 10));
    EXPECT_TRUE(res.applied) << res.message;
    double worst = 0;
    for (const auto& r : res.revisions) worst = std::max(worst, (r.p_WB - Motion::position(seconds(r.t))).norm());
    *end_error = res.revisions.back().p_WB - Motion::position(seconds(last));
    return worst;
  };
  Eigen::Vector3d shaped_end, constant_end;
  // ImuNoiseParams{}: the EuRoC random walk, 3e-3 m/s^2/sqrt(s); a held estimate known to 1e-3.
  const double shaped = worstError(1e-3, &shaped_end);
  const double constant = worstError(1e3, &constant_end);  // the walk negligible: constant shape
  std::printf("walking bias over 13 s: worst corrected position error %.3f m shaped, %.3f m constant\n", shaped,
              constant);
  // A steady ramp a*t is not the walk's expected shape, t (T - t / 2T): fitted to the same end
  // velocity it leaves a T^3 / 48 = 0.17 m at the end, the constant a T^3 / 12 = 0.68 m
  // (a = 0.0037 m/s^3, T = 13 s; uncorrected, a T^3 / 6 = 1.35 m).
  EXPECT_LT(shaped, 0.3 * constant);
  EXPECT_LT(shaped_end.norm(), 0.3 * constant_end.norm());
  EXPECT_LT(shaped, 0.2);
}

TEST(ConflictIntervalSmoother, AReidentifiedEndPositionFixesWhatTheVelocityCannot) {
  // The walking bias of the test above, with the map seen before the interval re-identified
  // after it: vision gives the end position, and the constant-plus-ramp correction fitted to it
  // and the velocities takes the whole walk out.
  ConflictIntervalSmoother::Options o = options();
  o.held_acceleration_sigma = 1e3;  // the velocity-only fit a constant
  const auto run = [&](const ConflictIntervalSmoother::ReidentifiedEnd* end, double* worst) {
    ConflictIntervalSmoother s(o);
    const Timestamp last = fillWindow(&s, 12.0);
    const auto res = s.finish(imuFor(seconds(last) + 0.1, walkingBias), ImuNoiseParams{}, kGravity,
                              Motion::position(seconds(last)) + Eigen::Vector3d(0.3, 0.2, -0.4),
                              trueVelocities(last, 10), end);
    EXPECT_TRUE(res.applied) << res.message;
    *worst = 0;
    for (const auto& r : res.revisions) *worst = std::max(*worst, (r.p_WB - Motion::position(seconds(r.t))).norm());
    return res;
  };
  double velocity_only = 0, with_end = 0, with_cabin = 0, with_far_end = 0;
  run(nullptr, &velocity_only);
  ConflictIntervalSmoother s0(o);
  const Timestamp last = fillWindow(&s0, 12.0);
  ConflictIntervalSmoother::ReidentifiedEnd end;
  end.p = Motion::position(seconds(last));
  end.sigma = 0.01;
  end.landmarks = 20;
  const auto res = run(&end, &with_end);
  EXPECT_TRUE(res.used_reidentified) << res.message;
  EXPECT_NE(res.message.find("20 re-identified landmarks"), std::string::npos) << res.message;
  std::printf("walking bias over 13 s: worst corrected position error %.4f m with the re-identified end, %.3f m "
              "velocities only\n", with_end, velocity_only);
  EXPECT_LT(with_end, 0.005);
  EXPECT_GT(velocity_only, 0.3);
  // An end 30 m off would need 0.36 m/s^2 (above smoothing_max_acceleration_correction): the
  // velocity-only correction stands.
  end.p.x() += 30.0;
  const auto far = run(&end, &with_far_end);
  EXPECT_FALSE(far.used_reidentified);
  EXPECT_NE(far.message.find("not used"), std::string::npos) << far.message;
  EXPECT_DOUBLE_EQ(with_far_end, velocity_only);
  end.p.x() -= 30.0;
  // The landmarks seen again are an elevator cabin's, 8 m below where the ride ended: no held
  // bias error explains that (3 x 0.5 x 0.01 x 13^2 = 2.5 m), and the end is not used.
  o.held_acceleration_sigma = 0.01;
  double shaped_only = 0;
  run(nullptr, &shaped_only);
  end.p.z() -= 8.0;
  const auto cabin = run(&end, &with_cabin);
  EXPECT_FALSE(cabin.used_reidentified);
  EXPECT_NE(cabin.message.find("not used"), std::string::npos) << cabin.message;
  EXPECT_DOUBLE_EQ(with_cabin, shaped_only);
}

TEST(ConflictIntervalSmoother, MovesTheConflictingFrameWithTheBody) {
  // The cabin's pose is measured from the body (vision against the cabin), so the body's
  // correction at a frame is the cabin's too. Only frames that published one get a revision.
  ConflictIntervalSmoother s(options());
  s.begin(kStart, Motion::position(0), Eigen::Quaterniond::Identity(), Motion::velocity(0), ImuBias{});
  const Eigen::Vector3d body_to_cabin(0.2, -0.3, 1.1);
  const Eigen::Quaterniond q_WS(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  std::map<Timestamp, Eigen::Vector3d> published;  // the drifted body positions the cabin was published with
  Timestamp t = kStart + kFramePeriod;
  for (int i = 0; i < 260; ++i, t += kFramePeriod) {
    s.addFrame(t, Eigen::Quaterniond::Identity());
    if (i == 240) s.markExit();
    if (i >= 10 && i < 240) {
      const Eigen::Vector3d p = Motion::position(seconds(t)) + Eigen::Vector3d(0.01 * i, 0, -0.02 * i);
      published[t] = p;
      s.setSecondary(t, p, p + body_to_cabin, q_WS);
      s.setSecondary(t - kFramePeriod / 2, p, Eigen::Vector3d::Zero(), q_WS);  // not a frame: ignored
    }
  }
  const Timestamp last = t - kFramePeriod;
  const auto res = s.finish(imuFor(seconds(last) + 0.1), steadyBiasImu(), kGravity, Motion::position(seconds(last)),
                            trueVelocities(last, 10));
  ASSERT_TRUE(res.applied) << res.message;
  ASSERT_EQ(res.secondary_revisions.size(), published.size());
  std::map<Timestamp, Eigen::Vector3d> revised;
  for (const auto& r : res.revisions) revised[r.t] = r.p_WB;
  for (const auto& sr : res.secondary_revisions) {
    ASSERT_EQ(published.count(sr.t), 1u);
    // The cabin moved by exactly what the body did at that frame.
    EXPECT_LT((sr.p_WB - (published[sr.t] + body_to_cabin) - (revised[sr.t] - published[sr.t])).norm(), 1e-12);
    // ...which puts it next to the corrected (here true) body position.
    EXPECT_LT((sr.p_WB - body_to_cabin - Motion::position(seconds(sr.t))).norm(), 1e-3);
    EXPECT_LT(sr.q_WB.angularDistance(q_WS), 1e-12);
  }
}

TEST(ConflictIntervalSmoother, RefusesAnEndVelocityThatIsNotTheWorlds) {
  // The interval closed while the cabin still moved at 2 m/s: vision's velocity is the cabin's
  // (a 0.3 m/s^2 correction over the 7 s window).
  ConflictIntervalSmoother s(options());
  const Timestamp last = fillWindow(&s, 6.0);
  const ImuBuffer imu = imuFor(seconds(last) + 0.1);
  auto settled = trueVelocities(last, 10);
  for (auto& v : settled) v.v.z() -= 2.0;
  const auto res = s.finish(imu, ImuNoiseParams{}, kGravity, Eigen::Vector3d::Zero(), settled);
  EXPECT_FALSE(res.applied);
  EXPECT_TRUE(res.revisions.empty());
  EXPECT_NE(res.message.find("smoothing_max_acceleration_correction"), std::string::npos) << res.message;
  EXPECT_FALSE(s.active());
}

TEST(ConflictIntervalSmoother, MissingImuOrVelocitiesIsAClearRefusal) {
  ConflictIntervalSmoother s(options());
  const Timestamp last = fillWindow(&s, 6.0);
  const ImuBuffer short_imu = imuFor(3.0);
  auto res = s.finish(short_imu, ImuNoiseParams{}, kGravity, Eigen::Vector3d::Zero(), trueVelocities(last, 10));
  EXPECT_FALSE(res.applied);
  EXPECT_NE(res.message.find("no IMU"), std::string::npos) << res.message;

  fillWindow(&s, 6.0);
  res = s.finish(imuFor(8.0), ImuNoiseParams{}, kGravity, Eigen::Vector3d::Zero(), {});
  EXPECT_FALSE(res.applied);
  EXPECT_NE(res.message.find("no settled velocity"), std::string::npos) << res.message;
}

TEST(ConflictIntervalSmoother, ASecondIntervalWhileSettlingExtendsTheWindow) {
  ConflictIntervalSmoother s(options());
  s.begin(kStart, Motion::position(0), Eigen::Quaterniond::Identity(), Motion::velocity(0), ImuBias{});
  Timestamp t = kStart + kFramePeriod;
  for (int i = 0; i < 40; ++i, t += kFramePeriod) s.addFrame(t, Eigen::Quaterniond::Identity());
  s.markExit();
  for (int i = 0; i < 5; ++i, t += kFramePeriod) s.addFrame(t, Eigen::Quaterniond::Identity());
  EXPECT_TRUE(s.exited());
  s.resumeInterval();
  EXPECT_FALSE(s.exited());
  for (int i = 0; i < 40; ++i, t += kFramePeriod) s.addFrame(t, Eigen::Quaterniond::Identity());
  EXPECT_FALSE(s.ready());
  s.markExit();
  for (int i = 0; i < 19; ++i, t += kFramePeriod) s.addFrame(t, Eigen::Quaterniond::Identity());
  EXPECT_FALSE(s.ready());
  s.addFrame(t, Eigen::Quaterniond::Identity());
  EXPECT_TRUE(s.ready());
  EXPECT_EQ(s.startTime(), kStart);
  // Frames out of order are ignored, never integrated backwards.
  s.addFrame(kStart, Eigen::Quaterniond::Identity());
  const auto res = s.finish(imuFor(seconds(t) + 0.1), ImuNoiseParams{}, kGravity, Motion::position(seconds(t)),
                            trueVelocities(t, 10));
  ASSERT_TRUE(res.applied) << res.message;
  EXPECT_EQ(res.revisions.size(), 105u);
}

TEST(ConflictIntervalSmoother, AWindowLongerThanItsLimitIsGivenUp) {
  ConflictIntervalSmoother::Options o = options();
  o.max_window_s = 5.0;
  ConflictIntervalSmoother s(o);
  s.begin(kStart, Motion::position(0), Eigen::Quaterniond::Identity(), Motion::velocity(0), ImuBias{});
  Timestamp t = kStart + kFramePeriod;
  for (; seconds(t) <= 5.0 + 1e-9; t += kFramePeriod) s.addFrame(t, Eigen::Quaterniond::Identity());
  EXPECT_TRUE(s.active());
  s.addFrame(t, Eigen::Quaterniond::Identity());
  EXPECT_FALSE(s.active()) << "no IMU is kept for a window that can no longer be smoothed";
}

namespace {

/// The spread of the corrected end over many rides against the covariance finish() predicts.
struct RideSpread {
  Eigen::Vector3d sigma_predicted, sigma_actual;
  double nees = 0;
};

/// 300 rides of a 12 s interval, each with its own start errors drawn from the covariance
/// finish() is given (attitude, velocity, both held biases), IMU noise and bias walk drawn from
/// the noise model, one error common to the settled velocities and, with `reidentified_sigma`
/// > 0, an end position measured to that sigma.
RideSpread spreadOverRides(double reidentified_sigma) {
  ImuNoiseParams noise;  // EuRoC's densities
  const double sigma_tilt = 5e-4, sigma_v0 = 5e-3, sigma_bg = 5e-5, sigma_ba = 5e-3;
  ConflictIntervalSmoother::StartCovariance start = ConflictIntervalSmoother::StartCovariance::Zero();
  start.diagonal() << Eigen::Vector3d::Constant(sigma_tilt * sigma_tilt), Eigen::Vector3d::Constant(sigma_v0 * sigma_v0),
      Eigen::Vector3d::Constant(sigma_bg * sigma_bg), Eigen::Vector3d::Constant(sigma_ba * sigma_ba);
  const ConflictIntervalSmoother::Options o = options();
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto draw = [&](double sigma) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * sigma;
  };
  const double dt = toSeconds(kImuPeriod);
  constexpr int kRides = 300;
  Eigen::Matrix3d predicted = Eigen::Matrix3d::Zero(), actual = Eigen::Matrix3d::Zero();
  RideSpread out;
  for (int ride = 0; ride < kRides; ++ride) {
    const Eigen::Vector3d tilt0 = draw(sigma_tilt), dv0 = draw(sigma_v0), dbg = draw(sigma_bg), dba = draw(sigma_ba);
    const Eigen::Vector3d dv_settled = draw(o.settled_velocity_sigma);
    // The IMU of this ride, and the orientation an estimator integrating its gyro with the held
    // bias would give at each frame (the truth stays level).
    ImuBuffer imu;
    Eigen::Vector3d bg_true(0.002, -0.001, 0.0015), ba_true = kTrueAccelBias;
    ImuBias held;
    held.gyro = bg_true + dbg;
    held.accel = ba_true + dba;
    Eigen::Quaterniond q_est = estimator::so3::expQuat(tilt0);
    std::map<Timestamp, Eigen::Quaterniond> orientation;
    for (Timestamp t = kStart; seconds(t) <= 13.2 + 1e-9; t += kImuPeriod) {
      ImuSample s;
      s.t = t;
      s.gyro = bg_true + draw(noise.gyroscope_noise_density / std::sqrt(dt));
      s.accel = Motion::accel(seconds(t)) - kGravity + ba_true + draw(noise.accelerometer_noise_density / std::sqrt(dt));
      EXPECT_EQ(imu.add(s, 0.1), ImuBuffer::AddResult::kAccepted);
      if ((t - kStart) % kFramePeriod == 0) orientation[t] = q_est;
      q_est = (q_est * estimator::so3::expQuat((s.gyro - held.gyro) * dt)).normalized();
      bg_true += draw(noise.gyroscope_random_walk * std::sqrt(dt));
      ba_true += draw(noise.accelerometer_random_walk * std::sqrt(dt));
    }
    ConflictIntervalSmoother s(o);
    s.begin(kStart, Motion::position(0), orientation.at(kStart), Motion::velocity(0) + dv0, held);
    Timestamp t = kStart + kFramePeriod;
    for (; seconds(t) <= 12.0 + 1e-9; t += kFramePeriod) s.addFrame(t, orientation.at(t));
    s.markExit();
    for (int i = 0; i < 20; ++i, t += kFramePeriod) s.addFrame(t, orientation.at(t));
    const Timestamp last = t - kFramePeriod;
    auto settled = trueVelocities(last, 10);
    for (auto& v : settled) v.v += dv_settled;
    ConflictIntervalSmoother::ReidentifiedEnd end;
    end.p = Motion::position(seconds(last)) + draw(reidentified_sigma);
    end.sigma = reidentified_sigma;
    end.landmarks = 30;
    const auto res = s.finish(imu, noise, kGravity, Motion::position(seconds(last)), settled,
                              reidentified_sigma > 0 ? &end : nullptr, &start);
    EXPECT_TRUE(res.applied) << res.message;
    EXPECT_TRUE(res.shift_covariance_valid) << res.message;
    EXPECT_EQ(res.used_reidentified, reidentified_sigma > 0) << res.message;
    if (!res.shift_covariance_valid) return out;
    const Eigen::Vector3d e = res.revisions.back().p_WB - Motion::position(seconds(last));
    actual += e * e.transpose() / kRides;
    predicted += res.shift_covariance / kRides;
    out.nees += e.dot(res.shift_covariance.inverse() * e) / kRides;
  }
  out.sigma_predicted = predicted.diagonal().cwiseSqrt();
  out.sigma_actual = actual.diagonal().cwiseSqrt();
  std::printf("corrected end over %d rides%s: sigma predicted %.3f / %.3f / %.3f m, actual %.3f / %.3f / %.3f m, "
              "NEES %.2f\n",
              kRides, reidentified_sigma > 0 ? " with a re-identified end" : "", out.sigma_predicted.x(),
              out.sigma_predicted.y(), out.sigma_predicted.z(), out.sigma_actual.x(), out.sigma_actual.y(),
              out.sigma_actual.z(), out.nees);
  return out;
}

}  // namespace

TEST(ConflictIntervalSmoother, TheCorrectedEndsCovarianceMatchesItsErrorOverManyRides) {
  for (const double reidentified_sigma : {0.0, 0.05}) {
    const RideSpread r = spreadOverRides(reidentified_sigma);
    // The errors are not negligible: a covariance of zero would fail below.
    EXPECT_GT(r.sigma_actual.minCoeff(), 0.02);
    // 300 draws know a sigma to about 4 %.
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(r.sigma_predicted[i] / r.sigma_actual[i], 1.0, 0.15) << "axis " << i << ", " << reidentified_sigma;
    EXPECT_NEAR(r.nees, 3.0, 0.5) << reidentified_sigma;
  }
  // Without the start's covariance there is none.
  ConflictIntervalSmoother s(options());
  const Timestamp last = fillWindow(&s, 12.0);
  const auto res = s.finish(imuFor(seconds(last) + 0.1), steadyBiasImu(), kGravity, Motion::position(seconds(last)),
                            trueVelocities(last, 10));
  EXPECT_TRUE(res.applied);
  EXPECT_FALSE(res.shift_covariance_valid);
}
