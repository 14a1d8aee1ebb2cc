#pragma once
#include <cstdint>
#include <deque>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mcvio/core/time.hpp"

namespace mcvio::estimator {

/// The landmarks the sliding window let go of, by track id, with their last world position. A
/// frontend that re-identifies a landmark it lost (the view came back after an occluder, or the
/// device came back) gives it its old track id; the window then triangulates it anew, and the
/// two positions say how far the estimate drifted in between. The conflict window uses this
/// after an IMU-dominated interval (ConflictIntervalSmoother::ReidentifiedEnd): the IMU alone
/// carried the position there, and the velocity after it constrains only three numbers.
class MapMemory {
 public:
  struct Options {
    double max_age_s = 130.0;         ///< longer than the conflict window's max_window_s
    std::size_t max_landmarks = 20000;  ///< the oldest go first
  };

  MapMemory() = default;
  explicit MapMemory(const Options& options) : options_(options) {}

  /// Remembers (or updates) a landmark's world position at time t; forgets what is older than
  /// max_age_s before t.
  void remember(std::uint64_t track_id, const Eigen::Vector3d& p_W, Timestamp t);
  /// The remembered position of track_id if it was remembered at or before `not_after`.
  const Eigen::Vector3d* find(std::uint64_t track_id, Timestamp not_after) const;
  /// Positions of the landmarks remembered at or before `not_after`, the latest `max_count` of
  /// them (by time, then track id).
  std::vector<Eigen::Vector3d> positionsUpTo(Timestamp not_after, std::size_t max_count) const;
  /// Moves every landmark remembered after t by `shift` (the window they were seen in moved).
  void shiftAfter(Timestamp t, const Eigen::Vector3d& shift);
  void clear();
  std::size_t size() const { return entries_.size(); }

  /// How far the window moved against the remembered map: a robust mean of current minus
  /// remembered positions (pairs further from their median than three robust standard
  /// deviations, clamped to [min_spread_m, max_spread_m], are left out: wrong
  /// re-identifications, landmarks that moved).
  struct Offset {
    bool valid = false;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< current minus remembered [m]
    double sigma = 0;                                   ///< standard error per axis [m]
    int inliers = 0;
    int pairs = 0;
  };
  /// Needs at least `min_inliers` agreeing pairs, and at least half of them.
  static Offset offsetOf(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& current_and_remembered,
                         int min_inliers, double min_spread_m = 0.05, double max_spread_m = 0.5,
                         double min_sigma_m = 0.01);

 private:
  struct Entry {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    Timestamp t = 0;
  };
  Options options_;
  std::unordered_map<std::uint64_t, Entry> entries_;
  std::deque<std::pair<Timestamp, std::uint64_t>> order_;  ///< (time remembered, track) oldest first
};

}  // namespace mcvio::estimator
