#include "mcvio/evaluation/ride_measurement.hpp"

#include <cmath>

namespace mcvio::evaluation {

namespace {

double percentError(double estimate, double truth) {
  if (!std::isfinite(estimate) || !std::isfinite(truth) || truth == 0) return RideMeasurement::kNaN;
  return 100.0 * std::abs(estimate - truth) / std::abs(truth);
}

}  // namespace

RideMeasurement RideMeasurement::measure(const Trajectory& estimate, const Trajectory& secondary,
                                         const Trajectory& ground_truth, const ConflictLabelTimeline& labels,
                                         const Eigen::Matrix3d& R_gt_est, double label_tolerance_s) {
  RideMeasurement m;
  const StampedPose* first = nullptr;
  const StampedPose* last = nullptr;
  for (const auto& p : estimate.poses()) {
    if (!labels.inConflictAt(p.t, label_tolerance_s).value_or(false)) continue;
    if (!first) first = &p;
    last = &p;
  }
  if (!first || !last || last->t <= first->t) return m;
  const auto g0 = ground_truth.interpolate(first->t, 0.1);
  const auto g1 = ground_truth.interpolate(last->t, 0.1);
  if (!g0 || !g1) return m;
  m.valid = true;
  m.truth_dz_m = g1->p.z() - g0->p.z();
  m.estimate_dz_m = last->p.z() - first->p.z();
  m.dz_error_percent = percentError(m.estimate_dz_m, m.truth_dz_m);
  const StampedPose* s_last = nullptr;
  for (const auto& s : secondary.poses())
    if (s.t >= first->t && s.t <= last->t) s_last = &s;
  if (!s_last) return m;
  m.secondary_dz_m = s_last->p.z();
  m.secondary_dz_error_percent = percentError(m.secondary_dz_m, m.truth_dz_m);
  const Eigen::Vector3d truth = g1->p - g0->p;
  const Eigen::Vector3d travelled = R_gt_est * s_last->p;
  m.travel_truth_m = truth.norm();
  m.secondary_travel_m = travelled.norm();
  if (m.travel_truth_m > 0) m.secondary_travel_error_percent = 100.0 * (travelled - truth).norm() / m.travel_truth_m;
  return m;
}

}  // namespace mcvio::evaluation
