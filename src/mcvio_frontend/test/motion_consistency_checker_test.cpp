// MotionConsistencyChecker on exact correspondences with known outliers, every code path.
#include "mcvio/frontend/motion_consistency_checker.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

namespace mcvio::frontend {
namespace {

constexpr double kFocal = 450.0;

struct Scenario {
  std::vector<MotionConsistencyChecker::Correspondence> tracks;
  std::vector<bool> outlier;
  Eigen::Matrix3d R;  // R_cur_prev
  Eigen::Vector3d t;
};

// 120 points 2-8 m ahead; every 6th moves on its own by 6 px perpendicular to its epipolar line
// (so even the depth-free epipolar test can see it). Pixel noise 0.2 px.
Scenario makeScenario(bool with_points, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.6, 0.6), depth(2.0, 8.0);
  std::normal_distribution<double> noise(0.0, 0.2 / kFocal);
  Scenario s;
  s.R = Eigen::AngleAxisd(0.03, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  s.t = Eigen::Vector3d(0.12, -0.02, 0.05);
  for (int i = 0; i < 120; ++i) {
    const Eigen::Vector3d X = Eigen::Vector3d(u(rng), u(rng) * 0.7, 1.0) * depth(rng);
    const Eigen::Vector3d Y = s.R * X + s.t;
    MotionConsistencyChecker::Correspondence c;
    c.prev_normalized = X.head<2>() / X.z() + Eigen::Vector2d(noise(rng), noise(rng));
    c.cur_normalized = Y.head<2>() / Y.z() + Eigen::Vector2d(noise(rng), noise(rng));
    c.has_point = with_points;
    c.point_prev = X;
    const bool out = i % 6 == 0;
    if (out) {
      const Eigen::Vector3d line = s.t.cross(s.R * c.prev_normalized.homogeneous());
      c.cur_normalized += line.head<2>().normalized() * (6.0 / kFocal);
    }
    s.tracks.push_back(c);
    s.outlier.push_back(out);
  }
  return s;
}

void expectLabels(const Scenario& s, const MotionConsistencyChecker::Result& r) {
  ASSERT_TRUE(r.valid);
  ASSERT_EQ(r.labels.size(), s.tracks.size());
  int wrong = 0;
  for (std::size_t i = 0; i < s.tracks.size(); ++i) {
    const TrackLabel expected = s.outlier[i] ? TrackLabel::kInconsistent : TrackLabel::kConsistent;
    wrong += r.labels[i] != expected ? 1 : 0;
  }
  EXPECT_LE(wrong, 2);
}

TEST(MotionConsistencyChecker, MetricWithGyroPriorEvenWhenThePriorIsBiased) {
  const Scenario s = makeScenario(true, 1);
  MotionConsistencyChecker checker(1.5, kFocal, 100, 8, 42);
  Eigen::Matrix3d prior = s.R;
  auto r = checker.check(s.tracks, &prior);
  EXPECT_TRUE(r.metric);
  expectLabels(s, r);
  EXPECT_LT((r.t_cur_prev - s.t).norm(), 0.01);
  // A gyro bias of 0.08 rad/s over 50 ms: 0.004 rad, 1.8 px of wrong prediction.
  prior = Eigen::AngleAxisd(0.004, Eigen::Vector3d::UnitY()).toRotationMatrix() * s.R;
  r = checker.check(s.tracks, &prior);
  expectLabels(s, r);
  EXPECT_LT(Eigen::AngleAxisd(r.R_cur_prev.transpose() * s.R).angle(), 1e-3);
}

TEST(MotionConsistencyChecker, AWideLensEdgeIsJudgedInItsOwnPixels) {
  // Half the tracks lie where a wide lens packs 5x more normalised plane into a pixel: their
  // 0.4 px of noise is 2 of the centre's pixels. Given their own scale they pass; the moving ones
  // (6 px there) still fail.
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 0.4 * 5.0 / kFocal);
  Scenario s = makeScenario(true, 3);
  int edge = 0;
  for (std::size_t i = 0; i < s.tracks.size(); i += 2) {
    auto& c = s.tracks[i];
    const Eigen::Vector3d Y = s.R * c.point_prev + s.t;
    c.cur_normalized = Y.head<2>() / Y.z() + Eigen::Vector2d(noise(rng), noise(rng));
    if (s.outlier[i]) {
      const Eigen::Vector3d line = s.t.cross(s.R * c.prev_normalized.homogeneous());
      c.cur_normalized += line.head<2>().normalized() * (6.0 * 5.0 / kFocal);
    }
    ++edge;
  }
  MotionConsistencyChecker checker(1.5, kFocal, 100, 8, 42);
  const Eigen::Matrix3d prior = s.R;
  const auto centre = checker.check(s.tracks, &prior);
  int centre_wrong = 0;
  for (std::size_t i = 0; i < s.tracks.size(); ++i)
    centre_wrong += centre.labels[i] != (s.outlier[i] ? TrackLabel::kInconsistent : TrackLabel::kConsistent) ? 1 : 0;
  EXPECT_GT(centre_wrong, edge / 4) << "the centre's scale fails static edge tracks";
  for (std::size_t i = 0; i < s.tracks.size(); i += 2) s.tracks[i].to_centre = Eigen::Matrix2d::Identity() / 5.0;
  const auto local = checker.check(s.tracks, &prior);
  expectLabels(s, local);
}

TEST(MotionConsistencyChecker, DominantMotionWinsOverAWrongGyroRotation) {
  // The camera sees mostly a vehicle interior that does not turn with the IMU: 0.05 rad (22 px)
  // of gyro rotation the images do not show. Labels follow the images' dominant motion.
  const Scenario s = makeScenario(true, 5);
  MotionConsistencyChecker checker(1.5, kFocal, 100, 8, 42);
  const Eigen::Matrix3d prior =
      Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix() * s.R;
  const auto r = checker.check(s.tracks, &prior);
  expectLabels(s, r);
}

TEST(MotionConsistencyChecker, MetricWithoutPrior) {
  const Scenario s = makeScenario(true, 2);
  MotionConsistencyChecker checker(1.5, kFocal, 100, 8, 42);
  const auto r = checker.check(s.tracks, nullptr);
  EXPECT_TRUE(r.metric);
  expectLabels(s, r);
}

TEST(MotionConsistencyChecker, TracksWithoutDepthMustBeInFrontOfTheCamera) {
  // Metric test with a third of the tracks lacking a stereo point. Some of those move along
  // their epipolar line, but the wrong way: only a point behind the camera would do that (a
  // device-attached object standing still while the camera turns looks like this).
  Scenario s = makeScenario(true, 6);
  for (std::size_t i = 0; i < s.tracks.size(); ++i) {
    if (i % 3 != 1) continue;
    auto& c = s.tracks[i];
    c.has_point = false;
    if (i % 9 != 1) continue;
    const Eigen::Vector3d far = s.R * c.prev_normalized.homogeneous();
    const Eigen::Vector2d a = far.head<2>() / far.z();
    const Eigen::Vector3d nearer = far + 0.5 * s.t;  // the same ray at 2 m
    const Eigen::Vector2d towards_near = (nearer.head<2>() / nearer.z() - a).normalized();
    c.cur_normalized = a - towards_near * (6.0 / kFocal);
    s.outlier[i] = true;
  }
  MotionConsistencyChecker checker(1.5, kFocal, 100, 8, 42, 0.1);
  const Eigen::Matrix3d prior = s.R;
  const auto r = checker.check(s.tracks, &prior);
  EXPECT_TRUE(r.metric);
  expectLabels(s, r);
}

TEST(MotionConsistencyChecker, EpipolarFallbacksWithoutStereoPoints) {
  const Scenario s = makeScenario(false, 3);
  MotionConsistencyChecker checker(1.5, kFocal, 200, 8, 42);
  const Eigen::Matrix3d prior = s.R;
  auto r = checker.check(s.tracks, &prior);
  EXPECT_FALSE(r.metric);
  expectLabels(s, r);
  EXPECT_GT(std::abs(r.t_cur_prev.normalized().dot(s.t.normalized())), 0.99);  // up to sign
  r = checker.check(s.tracks, nullptr);  // 5-point essential matrix
  EXPECT_FALSE(r.metric);
  expectLabels(s, r);
}

TEST(MotionConsistencyChecker, TooFewTracksStayUnknown) {
  Scenario s = makeScenario(true, 4);
  s.tracks.resize(5);
  MotionConsistencyChecker checker(1.5, kFocal, 100, 8, 42);
  const auto r = checker.check(s.tracks, nullptr);
  EXPECT_FALSE(r.valid);
  for (TrackLabel l : r.labels) EXPECT_EQ(l, TrackLabel::kUnknown);
}

}  // namespace
}  // namespace mcvio::frontend
