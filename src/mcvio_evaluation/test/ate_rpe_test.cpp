#include <cmath>

#include <gtest/gtest.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/evaluation/ate.hpp"
#include "mcvio/evaluation/rpe.hpp"
#include "synthetic_trajectory.hpp"

namespace mcvio::evaluation {
namespace {

Trajectory mapPoses(const Trajectory& in, const std::function<void(std::size_t, StampedPose&)>& f) {
  Trajectory out;
  for (std::size_t i = 0; i < in.size(); ++i) {
    StampedPose p = in[i];
    f(i, p);
    out.append(p);
  }
  return out;
}

TEST(Ate, ZeroForIdenticalTrajectories) {
  const Trajectory gt = test::lissajous(10, 20);
  for (auto a : {Alignment::kNone, Alignment::kSe3, Alignment::kPositionYaw}) {
    const AteResult r = computeAte(gt, gt, a);
    EXPECT_EQ(r.translation.count, gt.size());
    EXPECT_LT(r.translation.max, 1e-12) << toString(a);
    EXPECT_LT(r.rotation.max, 1e-6) << toString(a);
    EXPECT_EQ(r.unmatched, 0u);
  }
}

TEST(Ate, ConstantOffsetIsItsNormUnalignedAndZeroAligned) {
  const Trajectory gt = test::lissajous(10, 20);
  const Eigen::Vector3d offset(0.1, 0.2, -0.3);
  const Trajectory est = mapPoses(gt, [&](std::size_t, StampedPose& p) { p.p += offset; });
  const AteResult none = computeAte(est, gt, Alignment::kNone);
  EXPECT_NEAR(none.translation.rmse, offset.norm(), 1e-12);
  EXPECT_NEAR(none.translation.median, offset.norm(), 1e-12);
  EXPECT_NEAR(none.translation.max, offset.norm(), 1e-12);
  EXPECT_LT(computeAte(est, gt, Alignment::kSe3).translation.rmse, 1e-9);
  EXPECT_LT(computeAte(est, gt, Alignment::kPositionYaw).translation.rmse, 1e-9);
}

TEST(Ate, AlternatingHeightErrorSurvivesPositionYawAlignment) {
  // Height errors +-d around a constant shift: the shift and a yaw go, d stays at every pose.
  const Trajectory gt = test::lissajous(10, 20);
  const double d = 0.05;
  const Eigen::Isometry3d T(Eigen::Translation3d(1, 2, 3) * Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitZ()));
  const Trajectory est = mapPoses(gt.transformed(T), [&](std::size_t i, StampedPose& p) { p.p.z() += (i % 2 ? d : -d); });
  ASSERT_EQ(gt.size() % 2, 1u);  // odd count: the mean of the +-d is not zero, check it anyway
  const AteResult r = computeAte(est, gt, Alignment::kPositionYaw);
  const double n = static_cast<double>(gt.size());
  const double mean_shift = d / n;  // one more -d than +d
  const double expected_rmse = std::sqrt(d * d - mean_shift * mean_shift);
  EXPECT_NEAR(r.translation.rmse, expected_rmse, 1e-9);
  EXPECT_NEAR(r.translation.max, d + mean_shift, 1e-9);
}

TEST(Ate, StatisticsOfKnownErrors) {
  const Trajectory gt = test::lissajous(0.2, 20);  // 5 poses
  ASSERT_EQ(gt.size(), 5u);
  const Trajectory est = mapPoses(gt, [](std::size_t i, StampedPose& p) { p.p.x() += 0.1 * i; });
  const AteResult r = computeAte(est, gt, Alignment::kNone);
  EXPECT_NEAR(r.translation.mean, 0.2, 1e-12);
  EXPECT_NEAR(r.translation.median, 0.2, 1e-12);
  EXPECT_NEAR(r.translation.max, 0.4, 1e-12);
  EXPECT_NEAR(r.translation.min, 0.0, 1e-12);
  EXPECT_NEAR(r.translation.rmse, std::sqrt(0.06), 1e-12);
  // Only the last two poses: errors 0.3 and 0.4.
  const Timestamp t3 = gt[3].t;
  const ErrorStatistics late = r.translationWithin([&](Timestamp t) { return t >= t3; });
  EXPECT_EQ(late.count, 2u);
  EXPECT_NEAR(late.mean, 0.35, 1e-12);
  const ErrorStatistics none = r.translationWithin([](Timestamp) { return false; });
  EXPECT_EQ(none.count, 0u);
  EXPECT_TRUE(std::isnan(none.rmse));
}

TEST(Ate, RotationErrorOfAConstantBodyRotation) {
  const Trajectory gt = test::lissajous(10, 20);
  const Eigen::Quaterniond dq(Eigen::AngleAxisd(2.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()));
  const Trajectory est = mapPoses(gt, [&](std::size_t, StampedPose& p) { p.q = p.q * dq; });
  const AteResult r = computeAte(est, gt, Alignment::kSe3);
  EXPECT_LT(r.translation.max, 1e-9);
  EXPECT_NEAR(r.rotation.min, 2.0, 1e-6);
  EXPECT_NEAR(r.rotation.max, 2.0, 1e-6);
}

TEST(Ate, InterpolatesDenseGroundTruthAtEstimateTimes) {
  // 200 Hz ground truth, 20 Hz estimate shifted by 2.5 ms: straight-line motion interpolates exactly.
  const Trajectory gt = test::straightLine(10, 200, 1.5);
  const Trajectory est = test::straightLine(9, 20, 1.5, gt.startTime() + 2'500'000);
  const Trajectory shifted = mapPoses(est, [](std::size_t, StampedPose& p) { p.p.x() += 1.5 * 0.0025; });
  const AteResult r = computeAte(shifted, gt, Alignment::kNone);
  EXPECT_EQ(r.translation.count, est.size());
  EXPECT_LT(r.translation.max, 1e-9);
  // Nearest neighbour instead: 2.5 ms off, so the error is the 3.75 mm travelled meanwhile.
  AteOptions nearest;
  nearest.association.method = AssociationOptions::Method::kNearest;
  nearest.association.max_time_difference_s = 0.003;
  EXPECT_NEAR(computeAte(shifted, gt, Alignment::kNone, nearest).translation.mean, 1.5 * 0.0025, 1e-9);
  nearest.association.max_time_difference_s = 0.002;
  EXPECT_THROW(computeAte(shifted, gt, Alignment::kNone, nearest), InputError);
}

TEST(Ate, PosesOutsideGroundTruthAreCountedNotMatched) {
  const Trajectory gt = test::straightLine(5, 200, 1.0);
  const Trajectory est = test::straightLine(10, 20, 1.0);  // 5 s longer than the ground truth
  const AteResult r = computeAte(est, gt, Alignment::kNone);
  EXPECT_EQ(r.translation.count, 101u);
  EXPECT_EQ(r.unmatched, 100u);
}

TEST(Ate, NoCommonTimeNamesBothSources) {
  const Trajectory gt(test::straightLine(5, 200, 1.0).poses(), "gt.csv");
  const Trajectory est(test::straightLine(5, 20, 1.0, 100'000'000'000).poses(), "run/trajectory.tum");
  try {
    computeAte(est, gt, Alignment::kSe3);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gt.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("run/trajectory.tum"), std::string::npos) << e.what();
  }
}

TEST(Rpe, ScaleErrorOverOneSecond) {
  // 10 s at 20 Hz: 201 poses, 181 pairs one second apart, each 10 cm short of 10% too fast.
  const Trajectory gt = test::straightLine(10, 20, 1.0);
  const Trajectory est = test::straightLine(10, 20, 1.1);
  const RpeResult r = computeRpe(est, gt, RpeOptions::time(1.0));
  EXPECT_EQ(r.translation.count, 181u);
  EXPECT_NEAR(r.translation.min, 0.1, 1e-9);
  EXPECT_NEAR(r.translation.max, 0.1, 1e-9);
  EXPECT_NEAR(r.rotation.max, 0.0, 1e-9);
}

TEST(Rpe, YawDriftOverOneSecond) {
  // Standing still, the estimate turns 1 deg/s more than the truth.
  Trajectory gt, est;
  for (int i = 0; i <= 100; ++i) {
    const double s = i / 20.0;
    StampedPose g;
    g.t = 1'000'000'000 + Timestamp{i} * 50'000'000;
    g.p = {1, 2, 3};
    g.q = Eigen::AngleAxisd(0.5 * s, Eigen::Vector3d::UnitZ());
    StampedPose e = g;
    e.q = g.q * Eigen::AngleAxisd(s * M_PI / 180.0, Eigen::Vector3d::UnitZ());
    gt.append(g);
    est.append(e);
  }
  const RpeResult r = computeRpe(est, gt, RpeOptions::time(1.0));
  EXPECT_EQ(r.rotation.count, 81u);
  EXPECT_NEAR(r.rotation.min, 1.0, 1e-9);
  EXPECT_NEAR(r.rotation.max, 1.0, 1e-9);
  EXPECT_NEAR(r.translation.max, 0.0, 1e-12);
}

TEST(Rpe, ScaleErrorOverTwoMetres) {
  const Trajectory gt = test::straightLine(10, 20, 1.0);
  const Trajectory est = test::straightLine(10, 20, 1.1);
  const RpeResult r = computeRpe(est, gt, RpeOptions::distance(2.0));
  EXPECT_EQ(r.translation.count, 161u);  // pairs 40 frames (2 m of ground truth) apart
  EXPECT_NEAR(r.translation.mean, 0.2, 1e-9);
}

TEST(Rpe, IndependentOfTheEstimateWorldFrame) {
  const Trajectory gt = test::lissajous(10, 20);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(5, -3, 2);
  for (auto o : {RpeOptions::time(1.0), RpeOptions::distance(1.0)}) {
    const RpeResult r = computeRpe(gt.transformed(T), gt, o);
    EXPECT_GT(r.translation.count, 100u);
    EXPECT_LT(r.translation.max, 1e-9);
    EXPECT_LT(r.rotation.max, 1e-6);
  }
}

TEST(Rpe, PairsAcrossAHoleAreDropped) {
  // Estimate frames from 3 s to 6 s are missing: no pair may span the hole.
  const Trajectory gt = test::straightLine(10, 20, 1.0);
  Trajectory est;
  for (const auto& p : gt.poses()) {
    const double s = toSeconds(p.t - gt.startTime());
    if (s < 3.0 - 1e-9 || s > 6.0 + 1e-9) est.append(p);
  }
  const RpeResult r = computeRpe(est, gt, RpeOptions::time(1.0));
  // Kept: t in [0, 2.95] (pairs start at 0..1.95: 40) and [6.05, 10] (pairs start at 6.05..9: 60).
  EXPECT_EQ(r.translation.count, 40u + 60u);
  for (std::size_t i = 0; i < r.start_times.size(); ++i) EXPECT_NEAR(r.translation_errors[i], 0.0, 1e-9);
}

TEST(Rpe, RunShorterThanDeltaHasNoPairs) {
  const Trajectory gt = test::straightLine(0.5, 20, 1.0);
  const RpeResult r = computeRpe(gt, gt, RpeOptions::time(1.0));
  EXPECT_EQ(r.translation.count, 0u);
  EXPECT_TRUE(std::isnan(r.translation.rmse));
}

TEST(Rpe, RejectsBadOptions) {
  const Trajectory gt = test::straightLine(2, 20, 1.0);
  EXPECT_THROW(computeRpe(gt, gt, RpeOptions::time(0)), std::invalid_argument);
  RpeOptions o;
  o.tolerance = -1;
  EXPECT_THROW(computeRpe(gt, gt, o), std::invalid_argument);
}

}  // namespace
}  // namespace mcvio::evaluation
