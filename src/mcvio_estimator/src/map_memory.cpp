#include "mcvio/estimator/map_memory.hpp"

#include <algorithm>
#include <cmath>

namespace mcvio::estimator {

void MapMemory::remember(std::uint64_t track_id, const Eigen::Vector3d& p_W, Timestamp t) {
  if (!p_W.allFinite()) return;
  entries_[track_id] = {p_W, t};
  order_.emplace_back(t, track_id);
  const Timestamp oldest = t - fromSeconds(options_.max_age_s);
  // An entry in order_ is stale when its track was remembered again later.
  while (!order_.empty() && (order_.front().first < oldest || entries_.size() > options_.max_landmarks ||
                             order_.size() > 2 * options_.max_landmarks)) {
    const auto [when, id] = order_.front();
    order_.pop_front();
    const auto it = entries_.find(id);
    if (it != entries_.end() && it->second.t == when) entries_.erase(it);
  }
}

const Eigen::Vector3d* MapMemory::find(std::uint64_t track_id, Timestamp not_after) const {
  const auto it = entries_.find(track_id);
  return it != entries_.end() && it->second.t <= not_after ? &it->second.p : nullptr;
}

std::vector<Eigen::Vector3d> MapMemory::positionsUpTo(Timestamp not_after, std::size_t max_count) const {
  std::vector<std::pair<std::pair<Timestamp, std::uint64_t>, const Eigen::Vector3d*>> found;
  found.reserve(entries_.size());
  for (const auto& [id, e] : entries_)
    if (e.t <= not_after) found.push_back({{e.t, id}, &e.p});
  const auto later = [](const auto& a, const auto& b) { return a.first > b.first; };
  if (found.size() > max_count) {
    std::nth_element(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(max_count), found.end(), later);
    found.resize(max_count);
  }
  std::sort(found.begin(), found.end(), later);
  std::vector<Eigen::Vector3d> out;
  out.reserve(found.size());
  for (const auto& f : found) out.push_back(*f.second);
  return out;
}

void MapMemory::shiftAfter(Timestamp t, const Eigen::Vector3d& shift) {
  for (auto& [id, e] : entries_)
    if (e.t > t) e.p += shift;
}

void MapMemory::clear() {
  entries_.clear();
  order_.clear();
}

namespace {
double medianOf(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}
}  // namespace

MapMemory::Offset MapMemory::offsetOf(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& pairs,
                                      int min_inliers, double min_spread_m, double max_spread_m,
                                      double min_sigma_m) {
  Offset out;
  out.pairs = static_cast<int>(pairs.size());
  if (pairs.empty() || out.pairs < min_inliers) return out;
  std::vector<Eigen::Vector3d> d;
  d.reserve(pairs.size());
  for (const auto& [now, then] : pairs) d.push_back(now - then);
  Eigen::Vector3d median;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> axis;
    axis.reserve(d.size());
    for (const auto& x : d) axis.push_back(x[k]);
    median[k] = medianOf(axis);
  }
  std::vector<double> dist;
  dist.reserve(d.size());
  for (const auto& x : d) dist.push_back((x - median).norm());
  const double spread = std::clamp(3.0 * 1.4826 * medianOf(dist), min_spread_m, max_spread_m);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::vector<const Eigen::Vector3d*> in;
  for (std::size_t i = 0; i < d.size(); ++i)
    if (dist[i] <= spread) {
      sum += d[i];
      in.push_back(&d[i]);
    }
  out.inliers = static_cast<int>(in.size());
  if (out.inliers < min_inliers || 2 * out.inliers < out.pairs) return out;
  out.offset = sum / out.inliers;
  double ss = 0;
  for (const auto* x : in) ss += (*x - out.offset).squaredNorm();
  // Per axis: the scatter of the pairs over three axes, then the standard error of their mean.
  const double per_axis = out.inliers > 1 ? std::sqrt(ss / (3.0 * (out.inliers - 1))) : 0.0;
  out.sigma = std::max(min_sigma_m, per_axis / std::sqrt(static_cast<double>(out.inliers)));
  out.valid = out.offset.allFinite();
  return out;
}

}  // namespace mcvio::estimator
