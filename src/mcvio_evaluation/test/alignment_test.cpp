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
