#include "mcvio/estimator/landmark_registration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace mcvio::estimator {

namespace {

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    return static_cast<std::size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};
// Radius over tolerance at most this: an offset cell and a point are numbered within one word.
constexpr double kMaxCellsPerRadius = 2000.0;

CellKey cellOf(const Eigen::Vector3d& p, double size) {
  return {static_cast<std::int64_t>(std::floor(p.x() / size)), static_cast<std::int64_t>(std::floor(p.y() / size)),
          static_cast<std::int64_t>(std::floor(p.z() / size))};
}

// Bits needed to write n (0 for 0).
int bitWidth(std::uint64_t n) {
  int bits = 0;
  for (; n != 0; n >>= 1) ++bits;
  return bits;
}

// LSD radix sort of words below 2^bits: a few passes over the ballots instead of a comparison sort.
void radixSort(std::vector<std::uint64_t>* words, int bits) {
  constexpr int kDigit = 11;
  constexpr std::uint64_t kMask = (std::uint64_t{1} << kDigit) - 1;
  std::vector<std::uint64_t> sorted(words->size());
  for (int shift = 0; shift < bits; shift += kDigit) {
    std::vector<std::size_t> start(kMask + 2, 0);
    for (const std::uint64_t w : *words) ++start[((w >> shift) & kMask) + 1];
    for (std::size_t d = 0; d <= kMask; ++d) start[d + 1] += start[d];
    for (const std::uint64_t w : *words) sorted[start[(w >> shift) & kMask]++] = w;
    words->swap(sorted);
  }
}

}  // namespace

LandmarkRegistration::Result LandmarkRegistration::align(const std::vector<Eigen::Vector3d>& current,
                                                         const std::vector<Eigen::Vector3d>& remembered) const {
  Result res;
  const double R = options_.radius_m, tol = options_.tolerance_m;
  if (current.empty() || remembered.empty() || !(R > 0) || !(tol > 0) || R / tol > kMaxCellsPerRadius) return res;
  // An offset's tolerance cell as one number, ordered as the (x, y, z) triples are: offsets lie
  // within the radius, so each index is within [-K, K].
  const std::int64_t K = static_cast<std::int64_t>(std::ceil(R / tol)) + 1, W = 2 * K + 1;
  const int cell_bits = bitWidth(static_cast<std::uint64_t>(W * W * W - 1));
  const int point_bits = bitWidth(static_cast<std::uint64_t>(current.size() - 1));
  if (cell_bits + point_bits > 63) return res;
  const auto cellNumber = [K, W](const CellKey& k) {
    return static_cast<std::uint64_t>(((k.x + K) * W + (k.y + K)) * W + (k.z + K));
  };
  const auto cellOfNumber = [K, W](std::uint64_t n) {
    const auto v = static_cast<std::int64_t>(n);
    return CellKey{v / (W * W) - K, (v / W) % W - K, v % W - K};
  };
  // Remembered points on a grid of the search radius: a current point's candidates are in the
  // 27 cells around it.
  std::unordered_map<CellKey, std::vector<int>, CellHash> grid;
  for (std::size_t j = 0; j < remembered.size(); ++j)
    if (remembered[j].allFinite()) grid[cellOf(remembered[j], R)].push_back(static_cast<int>(j));
  // Candidate offsets of point i: candidates[first[i] .. first[i + 1]), and a ballot (cell, i),
  // one word, for each. Each point votes once per cell (a point near many remembered ones must not outvote
  // the others): sorted, a cell's votes are its distinct ballots.
  std::vector<Eigen::Vector3d> candidates;
  std::vector<std::size_t> first(current.size() + 1, 0);
  std::vector<std::uint64_t> ballots;
  for (std::size_t i = 0; i < current.size(); ++i) {
    first[i] = candidates.size();
    const Eigen::Vector3d& c = current[i];
    if (!c.allFinite()) continue;
    const CellKey k = cellOf(c, R);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({k.x + dx, k.y + dy, k.z + dz});
          if (it == grid.end()) continue;
          for (const int j : it->second) {
            const Eigen::Vector3d d = c - remembered[static_cast<std::size_t>(j)];
            if (d.norm() > R) continue;
            candidates.push_back(d);
            ballots.push_back((cellNumber(cellOf(d, tol)) << point_bits) | i);
          }
        }
  }
  first[current.size()] = candidates.size();
  radixSort(&ballots, cell_bits + point_bits);
  // (cell, votes) in cell order.
  std::vector<std::pair<std::uint64_t, int>> votes;
  for (std::size_t b = 0; b < ballots.size();) {
    const std::uint64_t cell = ballots[b] >> point_bits;
    int n = 0;
    for (; b < ballots.size() && (ballots[b] >> point_bits) == cell; ++b)
      if (b == 0 || ballots[b] != ballots[b - 1]) ++n;
    votes.emplace_back(cell, n);
  }
  if (votes.empty()) return res;
  // An offset near a cell border splits its votes: score each cell with its 26 neighbours.
  auto votesAt = [&votes, &cellNumber](const CellKey& k) {
    const std::uint64_t w = cellNumber(k);
    const auto it = std::lower_bound(votes.begin(), votes.end(), w,
                                     [](const std::pair<std::uint64_t, int>& v, std::uint64_t key) { return v.first < key; });
    return it != votes.end() && it->first == w ? it->second : 0;
  };
  auto score = [&votesAt](const CellKey& k) {
    int s = 0;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) s += votesAt({k.x + dx, k.y + dy, k.z + dz});
    return s;
  };
  auto centreOf = [tol](const CellKey& k) -> Eigen::Vector3d {
    const Eigen::Vector3d index(static_cast<double>(k.x), static_cast<double>(k.y), static_cast<double>(k.z));
    return (index + Eigen::Vector3d::Constant(0.5)) * tol;
  };
  // Only the most voted cells can hold an offset most points agree on; scoring every cell's
  // neighbourhood would cost more than the rest together.
  constexpr std::size_t kTopCells = 256;
  std::vector<std::pair<int, std::uint64_t>> most;
  most.reserve(votes.size());
  for (const auto& [w, n] : votes) most.emplace_back(n, w);
  const auto more_votes = [](const std::pair<int, std::uint64_t>& a, const std::pair<int, std::uint64_t>& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  };
  if (most.size() > kTopCells) {
    std::nth_element(most.begin(), most.begin() + kTopCells, most.end(), more_votes);
    most.resize(kTopCells);
  }
  std::sort(most.begin(), most.end(), more_votes);
  std::vector<std::pair<int, CellKey>> top;
  std::vector<int> scores;
  top.reserve(most.size());
  scores.reserve(most.size());
  for (const auto& [n, w] : most) {
    top.emplace_back(n, cellOfNumber(w));
    scores.push_back(score(top.back().second));
  }
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
        for (std::size_t c = first[i]; c < first[i + 1]; ++c) {
          const double e = (candidates[c] - *offset).norm();
          if (e < closest) {
            closest = e;
            chosen[i] = static_cast<int>(c);
          }
        }
        if (chosen[i] >= 0) {
          sum += candidates[static_cast<std::size_t>(chosen[i])];
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
      for (std::size_t c = first[i]; c < first[i + 1]; ++c) closest = std::min(closest, (candidates[c] - offset).squaredNorm());
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
    if (chosen[i] >= 0) res.pairs.emplace_back(current[i], current[i] - candidates[static_cast<std::size_t>(chosen[i])]);
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
