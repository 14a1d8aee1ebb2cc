#include "mcvio/frontend/gyro_integrator.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace mcvio::frontend {
namespace {

TEST(GyroIntegrator, ConstantRateGivesExactAngle) {
  GyroIntegrator g(30'000'000);
  const Eigen::Vector3d w(0.3, -0.2, 0.5);
  for (Timestamp t = 0; t <= 200'000'000; t += 5'000'000)
    ASSERT_TRUE(g.add({t, w, Eigen::Vector3d::Zero()}));
  Eigen::Matrix3d R;
  // Interval ends between samples exercise the interpolation at the boundaries.
  ASSERT_TRUE(g.rotation(12'500'000, 112'500'000, Eigen::Vector3d::Zero(), &R));
  const Eigen::Matrix3d expected =
      Eigen::AngleAxisd(w.norm() * 0.1, w.normalized()).toRotationMatrix();
  EXPECT_LT((R - expected).norm(), 1e-9);
  ASSERT_TRUE(g.rotation(12'500'000, 112'500'000, w, &R));
  EXPECT_LT((R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(GyroIntegrator, RefusesGapsAndBadSamples) {
  GyroIntegrator g(30'000'000);
  const Eigen::Vector3d w(0.1, 0, 0);
  ASSERT_TRUE(g.add({0, w, {}}));
  ASSERT_TRUE(g.add({5'000'000, w, {}}));
  EXPECT_FALSE(g.add({5'000'000, w, {}}));  // repeated time
  EXPECT_FALSE(g.add({1'000'000, w, {}}));  // backwards
  EXPECT_FALSE(
      g.add({6'000'000, Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 0, 0), {}}));
  ASSERT_TRUE(g.add({100'000'000, w, {}}));  // 95 ms hole
  Eigen::Matrix3d R;
  EXPECT_FALSE(g.rotation(0, 100'000'000, Eigen::Vector3d::Zero(), &R));
  EXPECT_TRUE(g.rotation(0, 5'000'000, Eigen::Vector3d::Zero(), &R));
  EXPECT_FALSE(
      g.rotation(100'000'000, 200'000'000, Eigen::Vector3d::Zero(), &R));  // beyond the data
}

TEST(GyroIntegrator, DropBeforeKeepsTheLeftNeighbour) {
  GyroIntegrator g(30'000'000);
  for (Timestamp t = 0; t <= 100'000'000; t += 5'000'000) g.add({t, Eigen::Vector3d(0, 0, 1), {}});
  g.dropBefore(52'000'000);
  Eigen::Matrix3d R;
  ASSERT_TRUE(g.rotation(52'000'000, 100'000'000, Eigen::Vector3d::Zero(), &R));
  EXPECT_NEAR(Eigen::AngleAxisd(R).angle(), 0.048, 1e-9);
}

}  // namespace
}  // namespace mcvio::frontend
