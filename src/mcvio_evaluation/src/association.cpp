#include "mcvio/evaluation/association.hpp"

#include <cmath>
#include <stdexcept>

namespace mcvio::evaluation {

void AssociationOptions::validate() const {
  if (!(max_interpolation_gap_s > 0) || !std::isfinite(max_interpolation_gap_s)) {
    throw std::invalid_argument("association.max_interpolation_gap_s must be > 0");
  }
  if (!(max_time_difference_s >= 0) || !std::isfinite(max_time_difference_s)) {
    throw std::invalid_argument("association.max_time_difference_s must be >= 0");
  }
}

AssociatedPoses associate(const Trajectory& estimate, const Trajectory& ground_truth,
                          const AssociationOptions& options) {
  options.validate();
  AssociatedPoses out;
  out.estimate.reserve(estimate.size());
  out.ground_truth.reserve(estimate.size());
  for (const auto& e : estimate.poses()) {
    if (options.method == AssociationOptions::Method::kInterpolate) {
      if (auto g = ground_truth.interpolate(e.t, options.max_interpolation_gap_s)) {
        out.estimate.push_back(e);
        out.ground_truth.push_back(*g);
        continue;
      }
    } else if (auto i = ground_truth.nearest(e.t, options.max_time_difference_s)) {
      StampedPose g = ground_truth[*i];
      g.t = e.t;
      out.estimate.push_back(e);
      out.ground_truth.push_back(g);
      continue;
    }
    ++out.unmatched;
  }
  return out;
}

}  // namespace mcvio::evaluation
