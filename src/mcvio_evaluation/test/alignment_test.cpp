#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "mcvio/evaluation/alignment.hpp"
#include "mcvio/evaluation/ate.hpp"
#include "synthetic_trajectory.hpp"

namespace mcvio::evaluation {
namespace {

std::vector<Eigen::Vector3d> positions(const Trajectory& t) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : t.poses()) out.push_back(p.p);
  return out;
}

Eigen::Isometry3d makeTransform(double yaw, double pitch, double roll, Eigen::Vector3d t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = t;
  return T;
}

TEST(Alignment, Se3RecoversAKnownRigidTransform) {
  const Trajectory gt = test::lissajous(20, 20);
  const Eigen::Isometry3d T = makeTransform(2.1, -0.4, 0.7, {3.0, -1.0, 0.5});
  // The estimate lives in a world rotated and shifted by T^-1.
  const Trajectory est = gt.transformed(T.inverse());
  const Eigen::Isometry3d found = alignSe3(positions(est), positions(gt));
  EXPECT_LT((found.linear() - T.linear()).norm(), 1e-9);
  EXPECT_LT((found.translation() - T.translation()).norm(), 1e-9);

  const AteResult ate = computeAte(est, gt, Alignment::kSe3);
  EXPECT_LT(ate.translation.max, 1e-9);
  EXPECT_LT(ate.rotation.max, 1e-6);
  EXPECT_EQ(ate.translation.count, gt.size());
}

TEST(Alignment, PositionYawRecoversAKnownYawAndTranslation) {
  const Trajectory gt = test::lissajous(20, 20);
  const Eigen::Isometry3d T = makeTransform(-2.5, 0, 0, {-4.0, 2.0, 1.5});
  const Trajectory est = gt.transformed(T.inverse());
  const Eigen::Isometry3d found = alignPositionYaw(positions(est), positions(gt));
  EXPECT_LT((found.linear() - T.linear()).norm(), 1e-9);
  EXPECT_LT((found.translation() - T.translation()).norm(), 1e-9);
  EXPECT_LT(computeAte(est, gt, Alignment::kPositionYaw).translation.max, 1e-9);
}

TEST(Alignment, PositionYawCannotUndoRollButSe3Can) {
  const Trajectory gt = test::lissajous(20, 20);
  const Eigen::Isometry3d T = makeTransform(0.3, 0, 0.2, {1.0, 0, 0});
  const Trajectory est = gt.transformed(T.inverse());
  EXPECT_LT(computeAte(est, gt, Alignment::kSe3).translation.rmse, 1e-9);
  // A 0.2 rad roll of a path spanning metres leaves centimetres that no yaw can remove.
  EXPECT_GT(computeAte(est, gt, Alignment::kPositionYaw).translation.rmse, 0.01);
}

TEST(Alignment, OnePointGivesATranslation) {
  const Eigen::Isometry3d T = alignSe3({{1, 2, 3}}, {{0, 0, 1}});
  EXPECT_TRUE(T.linear().isApprox(Eigen::Matrix3d::Identity()));
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(-1, -2, -2)));
}

TEST(Alignment, NoneIsIdentity) {
  const Trajectory gt = test::lissajous(5, 20);
  const Eigen::Isometry3d T = align(Alignment::kNone, positions(gt.transformed(makeTransform(1, 0, 0, {1, 1, 1}))), positions(gt));
  EXPECT_TRUE(T.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(Alignment, RejectsMismatchedOrEmptyInput) {
  EXPECT_THROW(alignSe3({}, {}), std::invalid_argument);
  EXPECT_THROW(alignPositionYaw({{0, 0, 0}}, {}), std::invalid_argument);
}

TEST(Alignment, NamesRoundTrip) {
  for (auto a : {Alignment::kNone, Alignment::kSe3, Alignment::kPositionYaw}) {
    EXPECT_EQ(alignmentFromString(toString(a)), a);
  }
  try {
    alignmentFromString("sim3");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sim3"), std::string::npos);
  }
}

}  // namespace
}  // namespace mcvio::evaluation

namespace mcvio::evaluation {
namespace {

TEST(Alignment, RunAtRestTakesTheRotationFromOrientations) {
  // A device at rest (positions within a millimetre) turning in place: positions cannot fix the
  // rotation, orientations can.
  Trajectory gt;
  for (int i = 0; i < 100; ++i) {
    StampedPose p;
    p.t = 1'000'000'000 + Timestamp{i} * 50'000'000;
    p.p = Eigen::Vector3d(1.0 + 0.001 * std::sin(0.3 * i), 2.0 + 0.001 * std::cos(0.7 * i), 0.5 + 0.0005 * std::sin(1.1 * i));
    p.q = Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.1 * std::sin(0.2 * i), Eigen::Vector3d::UnitX());
    gt.append(p);
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(1.2, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())).toRotationMatrix();
  T.translation() = Eigen::Vector3d(-2, 1, 0.3);
  const Trajectory est = gt.transformed(T.inverse());
  const AlignmentResult se3 = alignPoses(Alignment::kSe3, est.poses(), gt.poses());
  EXPECT_TRUE(se3.rotation_from_orientations);
  EXPECT_LT((se3.T_gt_est.linear() - T.linear()).norm(), 1e-9);
  EXPECT_LT((se3.T_gt_est.translation() - T.translation()).norm(), 1e-9);
  const AteResult ate = computeAte(est, gt, Alignment::kSe3);
  EXPECT_TRUE(ate.rotation_from_orientations);
  EXPECT_LT(ate.rotation.max, 1e-6);

  // Position+yaw on a yaw-only offset.
  Eigen::Isometry3d Y = Eigen::Isometry3d::Identity();
  Y.linear() = Eigen::AngleAxisd(-0.8, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Y.translation() = Eigen::Vector3d(3, 0, -1);
  const AlignmentResult posyaw = alignPoses(Alignment::kPositionYaw, gt.transformed(Y.inverse()).poses(), gt.poses());
  EXPECT_TRUE(posyaw.rotation_from_orientations);
  EXPECT_LT((posyaw.T_gt_est.linear() - Y.linear()).norm(), 1e-9);

  // With the threshold at zero the (arbitrary) position-based rotation is used instead.
  AlignmentOptions positions_only;
  positions_only.min_position_spread_m = 0;
  EXPECT_FALSE(alignPoses(Alignment::kSe3, est.poses(), gt.poses(), positions_only).rotation_from_orientations);
}

TEST(Alignment, MovingRunUsesPositions) {
  const Trajectory gt = test::lissajous(20, 20);
  const AlignmentResult r = alignPoses(Alignment::kSe3, gt.poses(), gt.poses());
  EXPECT_FALSE(r.rotation_from_orientations);
  EXPECT_TRUE(r.T_gt_est.isApprox(Eigen::Isometry3d::Identity(), 1e-9));
}

}  // namespace
}  // namespace mcvio::evaluation
