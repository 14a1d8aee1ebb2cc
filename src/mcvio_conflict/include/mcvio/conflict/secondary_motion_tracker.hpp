#pragma once
#include <deque>
#include <utility>

#include <Eigen/Geometry>

#include "mcvio/core/time.hpp"

namespace mcvio::conflict {

/// Motion of the conflicting frame S (the cabin, the vehicle, the carried object) during a
/// whole-view conflict. Vision alone tracks the body inside S (chained frame-to-frame motion);
/// the inertial estimate tracks the body in the world. Their difference is S in the world:
///   T_WS(k) = T_WB(k) * T_SB(k)^-1, with S = W at the start of the interval.
class SecondaryMotionTracker {
 public:
  /// Opens an interval at the body pose T_WB at time t.
  void begin(Timestamp t, const Eigen::Isometry3d& T_WB);
  /// Vision-only body motion from the previous frame to this one (a point of body k maps into
  /// body k-1 as T_prev_cur * X). An invalid increment breaks the chain until the next begin().
  void addVisionIncrement(const Eigen::Isometry3d& T_prev_cur, bool valid);
  /// Updates S with the current inertial body pose; returns false when no valid estimate exists.
  bool update(Timestamp t, const Eigen::Isometry3d& T_WB);
  void end() { active_ = false; }

  bool active() const { return active_; }
  bool valid() const { return active_ && chain_ok_ && have_estimate_; }
  const Eigen::Isometry3d& T_WS() const { return T_WS_; }
  /// Velocity of S over the last half second (per-frame differences are dominated by noise).
  const Eigen::Vector3d& v_WS() const { return v_WS_; }

 private:
  bool active_ = false, chain_ok_ = false, have_estimate_ = false;
  Eigen::Isometry3d T_SB_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_WS_ = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_WS_ = Eigen::Vector3d::Zero();
  Timestamp last_t_ = 0;
  std::deque<std::pair<Timestamp, Eigen::Vector3d>> recent_;
};

}  // namespace mcvio::conflict
