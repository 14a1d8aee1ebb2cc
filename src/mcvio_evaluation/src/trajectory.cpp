#include "mcvio/evaluation/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mcvio::evaluation {

namespace {

Timestamp secondsToNs(double s) { return static_cast<Timestamp>(std::llround(s * 1e9)); }

}  // namespace

Trajectory::Trajectory(std::vector<StampedPose> poses, std::string source)
    : source_(std::move(source)) {
  poses_.reserve(poses.size());
  for (const auto& p : poses) append(p);
}

void Trajectory::append(const StampedPose& pose) {
  if (!poses_.empty() && pose.t <= poses_.back().t) {
    throw std::invalid_argument((source_.empty() ? std::string("trajectory") : source_) +
                                ": pose time " + std::to_string(pose.t) +
                                " ns does not increase (previous " +
                                std::to_string(poses_.back().t) + " ns)");
  }
  poses_.push_back(pose);
}

Timestamp Trajectory::startTime() const { return poses_.empty() ? 0 : poses_.front().t; }
Timestamp Trajectory::endTime() const { return poses_.empty() ? 0 : poses_.back().t; }
double Trajectory::durationSeconds() const { return toSeconds(endTime() - startTime()); }

double Trajectory::pathLength() const {
  double length = 0;
  for (std::size_t i = 1; i < poses_.size(); ++i) length += (poses_[i].p - poses_[i - 1].p).norm();
  return length;
}

std::optional<StampedPose> Trajectory::interpolate(Timestamp t, double max_gap_s) const {
  if (poses_.empty() || t < poses_.front().t || t > poses_.back().t) return std::nullopt;
  const auto it = std::lower_bound(poses_.begin(), poses_.end(), t,
                                   [](const StampedPose& p, Timestamp v) { return p.t < v; });
  if (it->t == t) return *it;
  const StampedPose& b = *it;
  const StampedPose& a = *(it - 1);
  if (b.t - a.t > secondsToNs(max_gap_s)) return std::nullopt;
  const double s = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  StampedPose out;
  out.t = t;
  out.p = (1.0 - s) * a.p + s * b.p;
  out.q = a.q.slerp(s, b.q).normalized();
  return out;
}

std::optional<std::size_t> Trajectory::nearest(Timestamp t, double max_difference_s) const {
  if (poses_.empty()) return std::nullopt;
  const auto it = std::lower_bound(poses_.begin(), poses_.end(), t,
                                   [](const StampedPose& p, Timestamp v) { return p.t < v; });
  std::size_t best = static_cast<std::size_t>(it - poses_.begin());
  if (best == poses_.size()) {
    best = poses_.size() - 1;
  } else if (best > 0 && t - poses_[best - 1].t < poses_[best].t - t) {
    --best;
  }
  const Timestamp diff = poses_[best].t > t ? poses_[best].t - t : t - poses_[best].t;
  if (diff > secondsToNs(max_difference_s)) return std::nullopt;
  return best;
}

Trajectory Trajectory::transformed(const Eigen::Isometry3d& T) const {
  const Eigen::Quaterniond qT(T.linear());
  Trajectory out;
  out.source_ = source_;
  out.poses_.reserve(poses_.size());
  for (const auto& p : poses_) {
    StampedPose q = p;
    q.p = T * p.p;
    q.q = (qT * p.q).normalized();
    out.poses_.push_back(q);
  }
  return out;
}

}  // namespace mcvio::evaluation
