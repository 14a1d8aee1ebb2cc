#include "mcvio/frontend/gyro_integrator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <vector>

namespace mcvio::frontend {

bool GyroIntegrator::add(const ImuSample& sample) {
  if (!sample.gyro.allFinite()) return false;
  if (!samples_.empty() && sample.t <= samples_.back().t) return false;
  samples_.push_back(sample);
  return true;
}

void GyroIntegrator::dropBefore(Timestamp t) {
  // Keep one sample at or before t so interpolation at t still has a left neighbour.
  while (samples_.size() >= 2 && samples_[1].t <= t) samples_.pop_front();
}

Eigen::Vector3d GyroIntegrator::rateAt(Timestamp t) const {
  if (t <= samples_.front().t) return samples_.front().gyro;
  if (t >= samples_.back().t) return samples_.back().gyro;
  const auto it = std::lower_bound(samples_.begin(), samples_.end(), t,
                                   [](const ImuSample& s, Timestamp v) { return s.t < v; });
  const ImuSample& b = *it;
  const ImuSample& a = *(it - 1);
  const double w = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  return (1.0 - w) * a.gyro + w * b.gyro;
}

bool GyroIntegrator::rotation(Timestamp t0, Timestamp t1, const Eigen::Vector3d& gyro_bias,
                              Eigen::Matrix3d* R_b0_b1) const {
  if (samples_.empty() || t1 < t0) return false;
  // Data must cover [t0, t1] with no hole longer than max_gap_ns_, ends included.
  std::size_t first = 0;
  while (first + 1 < samples_.size() && samples_[first + 1].t <= t0) ++first;
  if (samples_[first].t > t0 + max_gap_ns_) return false;
  std::size_t last = first;
  while (last + 1 < samples_.size() && samples_[last].t < t1) {
    if (samples_[last + 1].t - samples_[last].t > max_gap_ns_) return false;
    ++last;
  }
  if (samples_[last].t < t1 - max_gap_ns_) return false;
  std::vector<Timestamp> knots{t0};
  for (std::size_t i = first; i <= last; ++i) {
    if (samples_[i].t > t0 && samples_[i].t < t1) knots.push_back(samples_[i].t);
  }
  knots.push_back(t1);
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (std::size_t i = 0; i + 1 < knots.size(); ++i) {
    const double dt = toSeconds(knots[i + 1] - knots[i]);
    if (dt <= 0) continue;
    const Eigen::Vector3d w = rateAt(knots[i] + (knots[i + 1] - knots[i]) / 2) - gyro_bias;
    const Eigen::Vector3d phi = w * dt;
    const double angle = phi.norm();
    const Eigen::Quaterniond dq = angle < 1e-12
                                      ? Eigen::Quaterniond::Identity()
                                      : Eigen::Quaterniond(Eigen::AngleAxisd(angle, phi / angle));
    q = q * dq;
  }
  q.normalize();
  *R_b0_b1 = q.toRotationMatrix();
  return true;
}

}  // namespace mcvio::frontend
