#include "mcvio/estimator/landmark_registration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <unordered_map>

namespace mcvio::estimator {

namespace {

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
  bool operator<(const CellKey& o) const { return std::make_tuple(x, y, z) < std::make_tuple(o.x, o.y, o.z); }
};
struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    return static_cast<std::size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};
CellKey cellOf(const Eigen::Vector3d& p, double size) {
  return {static_cast<std::int64_t>(std::floor(p.x() / size)), static_cast<std::int64_t>(std::floor(p.y() / size)),
          static_cast<std::int64_t>(std::floor(p.z() / size))};
}

}  // namespace

LandmarkRegistration::Result LandmarkRegistration::align(const std::vector<Eigen::Vector3d>& current,
                                                         const std::vector<Eigen::Vector3d>& remembered) const {
  Result res;
  const double R = options_.radius_m, tol = options_.tolerance_m;
  if (current.empty() || remembered.empty() || !(R > 0) || !(tol > 0)) return res;
  // Remembered points on a grid of the search radius: a current point's candidates are in the
  // 27 cells around it.
  std::unordered_map<CellKey, std::vector<int>, CellHash> grid;
  for (std::size_t j = 0; j < remembered.size(); ++j)
    if (remembered[j].allFinite()) grid[cellOf(remembered[j], R)].push_back(static_cast<int>(j));
  // Candidate offsets per current point, and one vote per current point and offset cell (a
  // point near many remembered ones must not outvote the others).
  std::vector<std::vector<Eigen::Vector3d>> candidates(current.size());
  std::unordered_map<CellKey, int, CellHash> votes;
  for (std::size_t i = 0; i < current.size(); ++i) {
    const Eigen::Vector3d& c = current[i];
    if (!c.allFinite()) continue;
    const CellKey k = cellOf(c, R);
    std::vector<CellKey> voted;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({k.x + dx, k.y + dy, k.z + dz});
          if (it == grid.end()) continue;
          for (const int j : it->second) {
            const Eigen::Vector3d d = c - remembered[static_cast<std::size_t>(j)];
            if (d.norm() > R) continue;
            candidates[i].push_back(d);
            voted.push_back(cellOf(d, tol));
          }
        }
    std::sort(voted.begin(), voted.end());
    voted.erase(std::unique(voted.begin(), voted.end()), voted.end());
    for (const CellKey& v : voted) ++votes[v];
  }
  if (votes.empty()) return res;
  // An offset near a cell border splits its votes: score each cell with its 26 neighbours.
  auto score = [&votes](const CellKey& k) {
    int s = 0;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = votes.find({k.x + dx, k.y + dy, k.z + dz});
          if (it != votes.end()) s += it->second;
        }
    return s;
  };
  auto centreOf = [tol](const CellKey& k) -> Eigen::Vector3d {
    const Eigen::Vector3d index(static_cast<double>(k.x), static_cast<double>(k.y), static_cast<double>(k.z));
    return (index + Eigen::Vector3d::Constant(0.5)) * tol;
  };
  // Only the most voted cells can hold an offset most points agree on; scoring every cell's
  // neighbourhood would cost more than the rest together.
  constexpr std::size_t kTopCells = 256;
  std::vector<std::pair<int, CellKey>> top;
  top.reserve(votes.size());
  for (const auto& [k, n] : votes) top.emplace_back(n, k);
  const auto more_votes = [](const std::pair<int, CellKey>& a, const std::pair<int, CellKey>& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  };
  if (top.size() > kTopCells) {
    std::nth_element(top.begin(), top.begin() + kTopCells, top.end(), more_votes);
    top.resize(kTopCells);
  }
  std::sort(top.begin(), top.end(), more_votes);  // the answer does not depend on the hash map's order
  std::vector<int> scores;
  scores.reserve(top.size());
  for (const auto& [n, k] : top) scores.push_back(score(k));
  // The best-scoring of those cells further than `exclude` from `away` (ties: the most voted).
  auto bestCell = [&](const Eigen::Vector3d& away, double exclude, CellKey* out) {
    int best_score = -1;
    for (std::size_t i = 0; i < top.size(); ++i) {
      if (exclude > 0 && (centreOf(top[i].second) - away).norm() <= exclude) continue;
      if (scores[i] > best_score) {
        best_score = scores[i];
        *out = top[i].second;
      }
    }
    return best_score >= 0;
  };
  // Each current point's candidate closest to the offset, if within two tolerances; the offset
  // becomes their mean. Returns how many points agree.
  std::vector<int> chosen(current.size(), -1);
  auto refine = [&](Eigen::Vector3d* offset) {
    int n = 0;
    for (int round = 0; round < 3; ++round) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      n = 0;
      for (std::size_t i = 0; i < current.size(); ++i) {
        chosen[i] = -1;
        double closest = 2.0 * tol;
        for (std::size_t c = 0; c < candidates[i].size(); ++c) {
          const double e = (candidates[i][c] - *offset).norm();
          if (e < closest) {
            closest = e;
            chosen[i] = static_cast<int>(c);
          }
        }
        if (chosen[i] >= 0) {
          sum += candidates[i][static_cast<std::size_t>(chosen[i])];
          ++n;
        }
      }
      if (n == 0) return 0;
      *offset = sum / n;
    }
    return n;
  };
  // How sharply the points agree with an offset: each point's closest candidate under a Gaussian
  // kernel of half a tolerance. The true offset's pairs scatter with the landmarks' noise, a
  // chance offset's spread over the whole agreement sphere.
  auto sharpness = [&](const Eigen::Vector3d& offset) {
    const double s2 = 2.0 * 0.25 * tol * tol;
    double sum = 0;
    for (std::size_t i = 0; i < current.size(); ++i) {
      double closest = std::numeric_limits<double>::infinity();
      for (const auto& d : candidates[i]) closest = std::min(closest, (d - offset).squaredNorm());
      if (std::isfinite(closest)) sum += std::exp(-closest / s2);
    }
    return sum;
  };
  // A distinct offset: one a repeated texture would give lies a period away; closer than this
  // it is the same offset's spread.
  const double distinct = std::max(3.0 * tol, 0.25);
  CellKey best{0, 0, 0};
  bestCell(Eigen::Vector3d::Zero(), 0.0, &best);
  Eigen::Vector3d offset = centreOf(best);
  res.support = refine(&offset);
  res.sharpness = sharpness(offset);
  res.offset = offset;
  for (std::size_t i = 0; i < current.size(); ++i)
    if (chosen[i] >= 0) res.pairs.emplace_back(current[i], current[i] - candidates[i][static_cast<std::size_t>(chosen[i])]);
  // The best cell away from it, refined the same way; one that drifts back into the best offset
  // was its tail.
  CellKey second{0, 0, 0};
  if (bestCell(offset, distinct, &second)) {
    Eigen::Vector3d runner_up = centreOf(second);
    const int agree = refine(&runner_up);
    if ((runner_up - offset).norm() > distinct) {
      res.runner_up = agree;
      res.runner_up_sharpness = sharpness(runner_up);
    }
  }
  const double needed = std::max(static_cast<double>(options_.min_points), options_.min_fraction * static_cast<double>(current.size()));
  res.valid = static_cast<double>(res.support) >= needed &&
              res.runner_up_sharpness <= options_.max_ambiguity * res.sharpness;
  return res;
}

}  // namespace mcvio::estimator
