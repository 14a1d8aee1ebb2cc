#include "mcvio/estimator/imu_buffer.hpp"

#include <algorithm>
#include <sstream>

namespace mcvio::estimator {

namespace {

ImuSample interpolate(const ImuSample& a, const ImuSample& b, Timestamp t) {
  const double s = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  ImuSample out;
  out.t = t;
  out.gyro = (1 - s) * a.gyro + s * b.gyro;
  out.accel = (1 - s) * a.accel + s * b.accel;
  return out;
}

}  // namespace

ImuBuffer::AddResult ImuBuffer::add(const ImuSample& sample, double max_gap_s, std::string* message) {
  if (!sample.gyro.allFinite() || !sample.accel.allFinite()) {
    if (message != nullptr) *message = "IMU sample at t=" + std::to_string(sample.t) + " ns has non-finite values; skipped";
    return AddResult::kRejectedNonFinite;
  }
  if (!samples_.empty() && sample.t <= samples_.back().t) {
    if (message != nullptr) {
      std::ostringstream os;
      os << "IMU sample at t=" << sample.t << " ns is " << (sample.t == samples_.back().t ? "a duplicate" : "older")
         << " (last accepted t=" << samples_.back().t << " ns); skipped";
      *message = os.str();
    }
    return AddResult::kRejectedNotIncreasing;
  }
  if (message != nullptr) {
    message->clear();
    if (!samples_.empty() && toSeconds(sample.t - samples_.back().t) > max_gap_s) {
      std::ostringstream os;
      os << "IMU gap of " << toSeconds(sample.t - samples_.back().t) << " s before t=" << sample.t << " ns";
      *message = os.str();
    }
  }
  samples_.push_back(sample);
  return AddResult::kAccepted;
}

bool ImuBuffer::extract(Timestamp t0, Timestamp t1, std::vector<ImuSample>* out, double* max_gap_s) const {
  out->clear();
  if (samples_.empty() || t1 <= t0 || samples_.front().t > t0 || samples_.back().t < t1) return false;
  auto it = std::upper_bound(samples_.begin(), samples_.end(), t0,
                             [](Timestamp t, const ImuSample& s) { return t < s.t; });
  // it: first sample strictly after t0; its predecessor is at or before t0.
  const ImuSample& before = *(it - 1);
  out->push_back(before.t == t0 ? before : interpolate(before, *it, t0));
  for (; it != samples_.end() && it->t < t1; ++it) out->push_back(*it);
  if (it == samples_.end()) return false;
  out->push_back(it->t == t1 ? *it : interpolate(*(it - 1), *it, t1));
  if (max_gap_s != nullptr) {
    // Gaps are measured between real samples, including the ones bracketing the interval.
    double gap = 0;
    auto first = std::upper_bound(samples_.begin(), samples_.end(), t0,
                                  [](Timestamp t, const ImuSample& s) { return t < s.t; }) - 1;
    for (auto j = first; j != it; ++j) gap = std::max(gap, toSeconds((j + 1)->t - j->t));
    *max_gap_s = gap;
  }
  return true;
}

std::vector<ImuSample> ImuBuffer::between(Timestamp t0, Timestamp t1) const {
  std::vector<ImuSample> out;
  for (const auto& s : samples_)
    if (s.t >= t0 && s.t <= t1) out.push_back(s);
  return out;
}

void ImuBuffer::dropBefore(Timestamp t) {
  while (samples_.size() > 2 && samples_[1].t <= t) samples_.pop_front();
}

}  // namespace mcvio::estimator
