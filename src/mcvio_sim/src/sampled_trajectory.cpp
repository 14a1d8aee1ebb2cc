#include "mcvio/sim/sampled_trajectory.hpp"

#include <algorithm>
#include <stdexcept>

namespace mcvio::sim {

SampledTrajectory::SampledTrajectory(std::vector<dataset::GroundTruthState> samples)
    : samples_(std::move(samples)) {
  if (samples_.size() < 2) throw std::invalid_argument("SampledTrajectory needs two samples");
  for (size_t i = 1; i < samples_.size(); ++i) {
    if (samples_[i].t <= samples_[i - 1].t)
      throw std::invalid_argument("SampledTrajectory: time not increasing at sample " +
                                  std::to_string(i));
  }
}

KinematicState SampledTrajectory::evaluate(Timestamp t) const {
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), t,
                                   [](Timestamp v, const dataset::GroundTruthState& s) { return v < s.t; });
  size_t i1 = static_cast<size_t>(it - samples_.begin());
  i1 = std::clamp<size_t>(i1, 1, samples_.size() - 1);
  const dataset::GroundTruthState& a = samples_[i1 - 1];
  const dataset::GroundTruthState& b = samples_[i1];
  const double dt = toSeconds(b.t - a.t);
  const double u = std::clamp(toSeconds(t - a.t) / dt, 0.0, 1.0);

  KinematicState s;
  s.p_wb = a.p_WB + u * (b.p_WB - a.p_WB);
  s.q_wb = a.q_WB.slerp(u, b.q_WB).normalized();
  s.v_w = a.v_WB + u * (b.v_WB - a.v_WB);
  s.a_w = (b.v_WB - a.v_WB) / dt;
  const Eigen::AngleAxisd delta(a.q_WB.conjugate() * b.q_WB);
  s.omega_b = delta.axis() * delta.angle() / dt;
  return s;
}

}  // namespace mcvio::sim
