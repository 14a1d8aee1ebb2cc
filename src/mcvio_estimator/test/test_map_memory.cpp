// Unit tests of MapMemory: what the window let go of, found again by track id, and the robust
// offset of the window against it.
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "mcvio/estimator/map_memory.hpp"

using namespace mcvio;
using estimator::MapMemory;

TEST(MapMemory, FindsALandmarkRememberedBeforeTheGivenTime) {
  MapMemory m;
  m.remember(7, {1, 2, 3}, fromSeconds(10.0));
  ASSERT_NE(m.find(7, fromSeconds(10.0)), nullptr);
  EXPECT_EQ(*m.find(7, fromSeconds(12.0)), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(m.find(7, fromSeconds(9.0)), nullptr);  // remembered after that
  EXPECT_EQ(m.find(8, fromSeconds(12.0)), nullptr);
  // Seen again and let go of again: the later position counts, stamped later.
  m.remember(7, {1, 2, 4}, fromSeconds(11.0));
  EXPECT_EQ(m.find(7, fromSeconds(10.5)), nullptr);
  EXPECT_EQ(*m.find(7, fromSeconds(11.0)), Eigen::Vector3d(1, 2, 4));
  EXPECT_EQ(m.size(), 1u);
  m.remember(9, {0, 0, std::numeric_limits<double>::quiet_NaN()}, fromSeconds(11.0));
  EXPECT_EQ(m.size(), 1u) << "a non-finite position is not remembered";
}

TEST(MapMemory, ForgetsWhatIsTooOldOrTooMuch) {
  MapMemory::Options o;
  o.max_age_s = 5.0;
  o.max_landmarks = 100;
  MapMemory m(o);
  m.remember(1, {0, 0, 0}, fromSeconds(0.0));
  m.remember(2, {0, 0, 0}, fromSeconds(4.0));
  m.remember(3, {0, 0, 0}, fromSeconds(6.0));
  EXPECT_EQ(m.find(1, fromSeconds(6.0)), nullptr);
  EXPECT_NE(m.find(2, fromSeconds(6.0)), nullptr);
  for (std::uint64_t id = 10; id < 400; ++id) m.remember(id, {0, 0, 0}, fromSeconds(6.0));
  EXPECT_EQ(m.size(), 100u);
  EXPECT_NE(m.find(399, fromSeconds(6.0)), nullptr);
  EXPECT_EQ(m.find(2, fromSeconds(6.0)), nullptr) << "the oldest go first";
  m.clear();
  EXPECT_EQ(m.size(), 0u);
}

TEST(MapMemory, ShiftsOnlyWhatWasSeenAfterTheIntervalEnded) {
  MapMemory m;
  m.remember(1, {0, 0, 0}, fromSeconds(1.0));
  m.remember(2, {0, 0, 0}, fromSeconds(3.0));
  m.shiftAfter(fromSeconds(2.0), {0.5, 0, 0});
  EXPECT_EQ(*m.find(1, fromSeconds(5.0)), Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(*m.find(2, fromSeconds(5.0)), Eigen::Vector3d(0.5, 0, 0));
}

TEST(MapMemory, TheOffsetLeavesWrongReidentificationsOut) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::uniform_real_distribution<double> anywhere(-5.0, 5.0);
  const Eigen::Vector3d drift(0.8, -0.4, 0.15);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  for (int i = 0; i < 30; ++i) {
    const Eigen::Vector3d p(anywhere(rng), anywhere(rng), anywhere(rng));
    pairs.emplace_back(p + drift + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)), p);
  }
  for (int i = 0; i < 12; ++i)  // matched to the wrong landmark
    pairs.emplace_back(Eigen::Vector3d(anywhere(rng), anywhere(rng), anywhere(rng)),
                       Eigen::Vector3d(anywhere(rng), anywhere(rng), anywhere(rng)));
  const auto o = MapMemory::offsetOf(pairs, 8);
  ASSERT_TRUE(o.valid);
  EXPECT_EQ(o.pairs, 42);
  EXPECT_GE(o.inliers, 30);
  EXPECT_LE(o.inliers, 31);
  EXPECT_LT((o.offset - drift).norm(), 0.02) << o.offset.transpose();
  EXPECT_GT(o.sigma, 0.001);
  EXPECT_LT(o.sigma, 0.02);
}

TEST(MapMemory, TooFewOrDisagreeingPairsGiveNoOffset) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  for (int i = 0; i < 5; ++i) pairs.emplace_back(Eigen::Vector3d(i, 1, 0), Eigen::Vector3d(i, 0, 0));
  EXPECT_FALSE(MapMemory::offsetOf(pairs, 8).valid);
  EXPECT_TRUE(MapMemory::offsetOf(pairs, 5).valid);
  EXPECT_FALSE(MapMemory::offsetOf({}, 0).valid);
  // Two groups that disagree by metres: no half of them agrees.
  pairs.clear();
  for (int i = 0; i < 20; ++i)
    pairs.emplace_back(Eigen::Vector3d(i, i % 2 == 0 ? 3.0 * i : -3.0 * i, 0), Eigen::Vector3d(i, 0, 0));
  EXPECT_FALSE(MapMemory::offsetOf(pairs, 5).valid);
}

TEST(MapMemory, GivesTheLatestPositionsRememberedBeforeATime) {
  MapMemory m;
  for (std::uint64_t id = 1; id <= 5; ++id)
    m.remember(id, Eigen::Vector3d(static_cast<double>(id), 0, 0), fromSeconds(static_cast<double>(id)));
  const auto upto3 = m.positionsUpTo(fromSeconds(3.0), 10);
  ASSERT_EQ(upto3.size(), 3u);
  EXPECT_EQ(upto3[0], Eigen::Vector3d(3, 0, 0)) << "latest first";
  EXPECT_EQ(upto3[2], Eigen::Vector3d(1, 0, 0));
  const auto latest2 = m.positionsUpTo(fromSeconds(10.0), 2);
  ASSERT_EQ(latest2.size(), 2u);
  EXPECT_EQ(latest2[0], Eigen::Vector3d(5, 0, 0));
  EXPECT_EQ(latest2[1], Eigen::Vector3d(4, 0, 0));
  EXPECT_TRUE(m.positionsUpTo(fromSeconds(0.5), 10).empty());
}
