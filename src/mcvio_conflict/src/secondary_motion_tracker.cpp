#include "mcvio/conflict/secondary_motion_tracker.hpp"

namespace mcvio::conflict {

void SecondaryMotionTracker::begin(Timestamp t, const Eigen::Isometry3d& T_WB) {
  active_ = true;
  chain_ok_ = true;
  have_estimate_ = true;
  T_SB_ = T_WB;
  T_WS_.setIdentity();
  v_WS_.setZero();
  last_t_ = t;
  recent_.clear();
  recent_.emplace_back(t, Eigen::Vector3d::Zero());
}

void SecondaryMotionTracker::addVisionIncrement(const Eigen::Isometry3d& T_prev_cur, bool valid) {
  if (!active_) return;
  if (!valid || !T_prev_cur.matrix().allFinite()) {
    chain_ok_ = false;
    return;
  }
  T_SB_ = T_SB_ * T_prev_cur;
}

bool SecondaryMotionTracker::update(Timestamp t, const Eigen::Isometry3d& T_WB) {
  if (!active_ || !chain_ok_) return false;
  const Eigen::Isometry3d T_WS = T_WB * T_SB_.inverse();
  recent_.emplace_back(t, T_WS.translation());
  while (recent_.size() > 2 && toSeconds(t - recent_[1].first) >= 0.5) recent_.pop_front();
  const double dt = toSeconds(t - recent_.front().first);
  if (dt > 0) v_WS_ = (T_WS.translation() - recent_.front().second) / dt;
  T_WS_ = T_WS;
  last_t_ = t;
  have_estimate_ = true;
  return true;
}

}  // namespace mcvio::conflict
