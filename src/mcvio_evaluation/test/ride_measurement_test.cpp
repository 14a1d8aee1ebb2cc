// RideMeasurement: the ride over the labelled interval as a run saw it, for the elevator (heights)
// and the vehicle (whole displacement, the estimate's world turned into the ground truth's).
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "mcvio/core/time.hpp"
#include "mcvio/evaluation/ride_measurement.hpp"

using namespace mcvio::evaluation;
using mcvio::fromSeconds;

namespace {

struct Ride {
  Trajectory truth, estimate, secondary;
  ConflictLabelTimeline labels;
};

/// 6 s at 20 Hz; the frame moves `direction` 4 m/s from 1 s to 5 s (labelled); the estimate is
/// the truth in a world turned by `yaw`; the secondary frame is tracked from 1.4 s and says the
/// ride was `scale` times its length since then.
Ride makeRide(const Eigen::Vector3d& direction, double yaw_deg, double scale) {
  const Eigen::Matrix3d R_est_gt = Eigen::AngleAxisd(-yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<StampedPose> truth, estimate, secondary;
  std::vector<mcvio::dataset::ConflictLabel> labels;
  for (int k = 0; k <= 120; ++k) {
    const double t = 0.05 * k;
    StampedPose g;
    g.t = fromSeconds(t);
    g.p = Eigen::Vector3d(0.0, 0.0, 1.0) + 4.0 * std::clamp(t - 1.0, 0.0, 4.0) * direction;
    truth.push_back(g);
    StampedPose e = g;
    e.p = R_est_gt * g.p;
    estimate.push_back(e);
    const bool moving = t >= 1.0 && t <= 5.0;
    labels.push_back({g.t, moving, moving ? "ride" : "none", moving ? 1.0 : 0.0});
    if (t >= 1.4 && t <= 5.0) {
      StampedPose s;
      s.t = g.t;
      s.p = R_est_gt * (scale * 4.0 * (t - 1.4) * direction);
      secondary.push_back(s);
    }
  }
  return {Trajectory(truth, "truth"), Trajectory(estimate, "estimate"), Trajectory(secondary, "secondary"),
          ConflictLabelTimeline(labels, "labels")};
}

}  // namespace

TEST(RideMeasurement, ElevatorHeightsOfTheBodyAndTheCabin) {
  const Ride r = makeRide(Eigen::Vector3d::UnitZ(), 30.0, 0.9);
  const auto m = RideMeasurement::measure(r.estimate, r.secondary, r.truth, r.labels, Eigen::Matrix3d::Identity());
  ASSERT_TRUE(m.valid);
  EXPECT_NEAR(m.truth_dz_m, 16.0, 1e-9);
  EXPECT_NEAR(m.estimate_dz_m, 16.0, 1e-9);  // a yaw does not move heights
  EXPECT_NEAR(m.dz_error_percent, 0.0, 1e-9);
  EXPECT_NEAR(m.secondary_dz_m, 0.9 * 14.4, 1e-9);
  EXPECT_NEAR(m.secondary_dz_error_percent, 100.0 * (16.0 - 0.9 * 14.4) / 16.0, 1e-9);
}

TEST(RideMeasurement, VehicleTravelNeedsTheAlignmentsYaw) {
  const Ride r = makeRide(Eigen::Vector3d::UnitX(), 40.0, 1.0);
  const Eigen::Matrix3d R_gt_est = Eigen::AngleAxisd(40.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto aligned = RideMeasurement::measure(r.estimate, r.secondary, r.truth, r.labels, R_gt_est);
  ASSERT_TRUE(aligned.valid);
  EXPECT_NEAR(aligned.travel_truth_m, 16.0, 1e-9);
  EXPECT_NEAR(aligned.secondary_travel_m, 14.4, 1e-9);
  EXPECT_NEAR(aligned.secondary_travel_error_percent, 10.0, 1e-9);  // 1.6 m before the detection
  // Without the yaw the same travel points 40 degrees off: 69 % wrong.
  const auto unaligned = RideMeasurement::measure(r.estimate, r.secondary, r.truth, r.labels, Eigen::Matrix3d::Identity());
  EXPECT_GT(unaligned.secondary_travel_error_percent, 60.0);
}

TEST(RideMeasurement, NothingLabelledOrNoSecondaryFrame) {
  Ride r = makeRide(Eigen::Vector3d::UnitX(), 0.0, 1.0);
  const auto no_secondary = RideMeasurement::measure(r.estimate, Trajectory(), r.truth, r.labels, Eigen::Matrix3d::Identity());
  EXPECT_TRUE(no_secondary.valid);
  EXPECT_FALSE(std::isfinite(no_secondary.secondary_dz_m));
  EXPECT_FALSE(std::isfinite(no_secondary.secondary_travel_error_percent));
  std::vector<mcvio::dataset::ConflictLabel> clean;
  for (const auto& p : r.truth.poses()) clean.push_back({p.t, false, "none", 0.0});
  const auto none = RideMeasurement::measure(r.estimate, r.secondary, r.truth, ConflictLabelTimeline(clean, "clean"),
                                             Eigen::Matrix3d::Identity());
  EXPECT_FALSE(none.valid);
  EXPECT_FALSE(std::isfinite(none.truth_dz_m));
}
