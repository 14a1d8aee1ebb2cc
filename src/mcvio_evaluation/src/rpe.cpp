#include "mcvio/evaluation/rpe.hpp"

#include <cmath>
#include <stdexcept>

#include "mcvio/core/input_error.hpp"

namespace mcvio::evaluation {

RpeOptions RpeOptions::time(double seconds) {
  RpeOptions o;
  o.unit = Delta::kTime;
  o.delta = seconds;
  return o;
}

RpeOptions RpeOptions::distance(double metres) {
  RpeOptions o;
  o.unit = Delta::kDistance;
  o.delta = metres;
  return o;
}

void RpeOptions::validate() const {
  if (!(delta > 0) || !std::isfinite(delta)) throw std::invalid_argument("rpe.delta must be > 0");
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) {
    throw std::invalid_argument("rpe.tolerance must be >= 0");
  }
  association.validate();
}

RpeResult computeRpe(const Trajectory& estimate, const Trajectory& ground_truth,
                     const RpeOptions& options) {
  options.validate();
  const AssociatedPoses pairs = associate(estimate, ground_truth, options.association);
  if (pairs.size() == 0) {
    throw InputError("estimate " + estimate.source() + " and ground truth " + ground_truth.source() +
                     " share no time: no relative pose error");
  }
  const std::size_t n = pairs.size();
  // Separation of each pose from the first: time [s] or ground-truth path length [m].
  std::vector<double> s(n, 0.0);
  for (std::size_t i = 1; i < n; ++i) {
    s[i] = options.unit == RpeOptions::Delta::kTime
               ? toSeconds(pairs.estimate[i].t - pairs.estimate[0].t)
               : s[i - 1] + (pairs.ground_truth[i].p - pairs.ground_truth[i - 1].p).norm();
  }
  const double limit = options.delta * (1.0 + options.tolerance);
  // Floating sums: a separation equal to delta up to rounding counts as reaching it.
  const double reach = options.delta * (1.0 - 1e-9);
  RpeResult r;
  r.options = options;
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (j <= i) j = i + 1;
    while (j < n && s[j] - s[i] < reach) ++j;
    if (j >= n) break;
    if (s[j] - s[i] > limit) continue;
    const Eigen::Isometry3d dg =
        pairs.ground_truth[i].isometry().inverse() * pairs.ground_truth[j].isometry();
    const Eigen::Isometry3d de = pairs.estimate[i].isometry().inverse() * pairs.estimate[j].isometry();
    const Eigen::Isometry3d E = dg.inverse() * de;
    r.start_times.push_back(pairs.estimate[i].t);
    r.translation_errors.push_back(E.translation().norm());
    r.rotation_errors_deg.push_back(Eigen::AngleAxisd(E.linear()).angle() * 180.0 / M_PI);
  }
  r.translation = ErrorStatistics::of(r.translation_errors);
  r.rotation = ErrorStatistics::of(r.rotation_errors_deg);
  return r;
}

}  // namespace mcvio::evaluation
