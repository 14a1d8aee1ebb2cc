#pragma once
#include <cstdint>
#include <unordered_map>
#include <unordered_set>

namespace mcvio::conflict {

/// Selective resolution's memory: classifies each track by its history of verdicts in the
/// inertial frame. Disagreeing verdicts add a strike, agreeing ones take one away; at `strikes`
/// the track is declared moving and stays eliminated (a track id is never reused). A track whose
/// last `confirmations` verdicts agreed and that has no strikes left is confirmed static.
class LandmarkMotionClassifier {
 public:
  explicit LandmarkMotionClassifier(int strikes, int confirmations = 1)
      : strikes_(strikes), confirmations_(confirmations) {}
  /// Returns true when this verdict made the track moving.
  bool addVerdict(std::uint64_t track_id, bool inconsistent);
  bool isMoving(std::uint64_t track_id) const { return moving_.count(track_id) != 0; }
  bool isConfirmedStatic(std::uint64_t track_id) const { return confirmed_.count(track_id) != 0; }
  std::size_t movingCount() const { return moving_.size(); }
  /// Forgets tracks that ended (keeps the memory small on long runs).
  void forget(std::uint64_t track_id);
  void clear();

 private:
  int strikes_;
  int confirmations_;
  std::unordered_map<std::uint64_t, int> count_;
  std::unordered_map<std::uint64_t, int> agreeing_;  ///< consecutive agreeing verdicts
  std::unordered_set<std::uint64_t> moving_;
  std::unordered_set<std::uint64_t> confirmed_;
};

}  // namespace mcvio::conflict
