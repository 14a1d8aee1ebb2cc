// Unit tests of LandmarkRegistration: the offset between the landmarks of a window that drifted
// and the map remembered before, found without track ids.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "mcvio/estimator/landmark_registration.hpp"

using mcvio::estimator::LandmarkRegistration;

namespace {

/// Corners on the walls, floor and ceiling of a 6 x 5 x 3 m room, about as dense as a map the
/// window lets go of over 20 s (2000 points).
std::vector<Eigen::Vector3d> room(int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> face(0, 5);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d p(6.0 * u(*rng), 5.0 * u(*rng), 3.0 * u(*rng));
    switch (face(*rng)) {
      case 0: p.x() = 0; break;
      case 1: p.x() = 6; break;
      case 2: p.y() = 0; break;
      case 3: p.y() = 5; break;
      case 4: p.z() = 0; break;
      default: p.z() = 3; break;
    }
    pts.push_back(p);
  }
  return pts;
}

/// The window after the interval: `seen` of the remembered corners triangulated again with
/// `noise_m` per axis, moved by `drift`, plus `extra` corners of a room 20 m away that the map
/// does not reach.
std::vector<Eigen::Vector3d> window(const std::vector<Eigen::Vector3d>& map, int seen, const Eigen::Vector3d& drift,
                                    double noise_m, int extra, std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, noise_m);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < seen; ++i) pts.push_back(map[static_cast<std::size_t>(i * 7 % static_cast<int>(map.size()))] + drift + Eigen::Vector3d(n(*rng), n(*rng), n(*rng)));
  const auto others = room(extra, rng);
  for (const auto& p : others) pts.push_back(p + Eigen::Vector3d(20.0, 0.0, 0.0));
  return pts;
}

}  // namespace

TEST(LandmarkRegistration, FindsTheDriftOfACornerSetSeenAgainUnderNoise) {
  std::mt19937 rng(3);
  const auto map = room(2000, &rng);
  const Eigen::Vector3d drift(1.2, -0.7, 0.4);
  // 4 cm per axis: 7 cm in 3-D, about what the window's fresh landmarks scatter by.
  const auto cur = window(map, 150, drift, 0.04, 40, &rng);
  const auto r = LandmarkRegistration().align(cur, map);
  ASSERT_TRUE(r.valid) << "support " << r.support << " sharpness " << r.sharpness << " runner-up "
                       << r.runner_up_sharpness;
  EXPECT_LT((r.offset - drift).norm(), 0.02);
  EXPECT_GE(r.support, 130);
  EXPECT_LT(r.runner_up_sharpness, 0.5 * r.sharpness);
  // Every pair it gives is one of the corners seen again, within two tolerances of the offset.
  ASSERT_EQ(r.pairs.size(), static_cast<std::size_t>(r.support));
  for (const auto& [now, then] : r.pairs) EXPECT_LT((now - then - r.offset).norm(), 0.16 + 1e-12);
}

TEST(LandmarkRegistration, RefusesADriftBeyondItsRadius) {
  std::mt19937 rng(4);
  const auto map = room(2000, &rng);
  const Eigen::Vector3d drift(5.3, 1.5, 0.0);  // 5.5 m
  const auto cur = window(map, 150, drift, 0.04, 40, &rng);
  const auto r = LandmarkRegistration().align(cur, map);  // radius 5 m
  EXPECT_FALSE(r.valid) << "offset " << r.offset.transpose() << " support " << r.support;
  LandmarkRegistration::Options wide;
  wide.radius_m = 6.5;
  const auto w = LandmarkRegistration(wide).align(cur, map);
  ASSERT_TRUE(w.valid);
  EXPECT_LT((w.offset - drift).norm(), 0.02);
}

TEST(LandmarkRegistration, RefusesAPlaceItHasNotSeen) {
  std::mt19937 rng(5);
  const auto map = room(2000, &rng);
  // A room of the same size and density, none of whose corners the map holds (the floor an
  // elevator opened onto).
  std::vector<Eigen::Vector3d> cur = room(190, &rng);
  const auto r = LandmarkRegistration().align(cur, map);
  EXPECT_FALSE(r.valid) << "support " << r.support << " of " << cur.size() << ", sharpness " << r.sharpness
                        << " runner-up " << r.runner_up_sharpness;
}

TEST(LandmarkRegistration, RefusesARepeatedTextureItCannotTellApart) {
  std::mt19937 rng(6);
  // The same corners twice, 1.5 m apart along the wall: the window matches either copy.
  auto map = room(1000, &rng);
  const std::size_t n = map.size();
  for (std::size_t i = 0; i < n; ++i) map.push_back(map[i] + Eigen::Vector3d(1.5, 0, 0));
  const auto cur = window(std::vector<Eigen::Vector3d>(map.begin(), map.begin() + 1000), 150,
                          Eigen::Vector3d(0.3, 0.2, 0.0), 0.04, 0, &rng);
  const auto r = LandmarkRegistration().align(cur, map);
  EXPECT_FALSE(r.valid) << "sharpness " << r.sharpness << " runner-up " << r.runner_up_sharpness;
  EXPECT_GT(r.runner_up_sharpness, 0.6 * r.sharpness);
}

TEST(LandmarkRegistration, NeedsEnoughOfTheWindowToAgree) {
  std::mt19937 rng(7);
  const auto map = room(2000, &rng);
  // 30 corners seen again among 170 new ones: under min_fraction 0.4 of the window.
  const auto cur = window(map, 30, Eigen::Vector3d(0.4, 0.1, 0.0), 0.04, 170, &rng);
  EXPECT_FALSE(LandmarkRegistration().align(cur, map).valid);
  LandmarkRegistration::Options lenient;
  lenient.min_fraction = 0.1;
  const auto r = LandmarkRegistration(lenient).align(cur, map);
  ASSERT_TRUE(r.valid);
  EXPECT_LT((r.offset - Eigen::Vector3d(0.4, 0.1, 0.0)).norm(), 0.03);
}

TEST(LandmarkRegistration, EmptyOrNonFiniteInputGivesNoAnswer) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const LandmarkRegistration reg;
  EXPECT_FALSE(reg.align({}, {{0, 0, 0}}).valid);
  EXPECT_FALSE(reg.align({{0, 0, 0}}, {}).valid);
  std::vector<Eigen::Vector3d> bad(50, Eigen::Vector3d(nan, 0, 0));
  EXPECT_FALSE(reg.align(bad, bad).valid);
  LandmarkRegistration::Options off;
  off.radius_m = 0;
  std::mt19937 rng(8);
  const auto map = room(500, &rng);
  EXPECT_FALSE(LandmarkRegistration(off).align(map, map).valid);
  LandmarkRegistration::Options fine;
  fine.tolerance_m = 0.001;  // 5000 cells a radius: more than the offset cells are numbered by
  EXPECT_FALSE(LandmarkRegistration(fine).align(map, map).valid);
}

// Fine cells near the limit (1000 a radius) number a few billion offset cells: the votes still
// count right.
TEST(LandmarkRegistration, FindsTheDriftWithFineCells) {
  std::mt19937 rng(9);
  const auto map = room(800, &rng);
  const Eigen::Vector3d drift(0.31, -0.42, 0.05);
  const auto cur = window(map, 120, drift, 0.0005, 0, &rng);
  LandmarkRegistration::Options o;
  o.radius_m = 2.0;
  o.tolerance_m = 0.002;
  const auto r = LandmarkRegistration(o).align(cur, map);
  ASSERT_TRUE(r.valid) << "support " << r.support;
  EXPECT_GE(r.support, 110);
  EXPECT_LT((r.offset - drift).norm(), 0.002);
}
