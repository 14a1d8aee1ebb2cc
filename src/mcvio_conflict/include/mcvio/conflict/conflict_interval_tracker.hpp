#pragma once
#include "mcvio/core/time.hpp"

namespace mcvio::conflict {

/// Turns per-frame evidence into conflict intervals [m-, m+] with hysteresis: an interval opens
/// after `enter_frames` consecutive frames with evidence and closes after `exit_frames`
/// consecutive frames without. Its start is the first frame of the evidence run, so a resolution
/// can act from there.
class ConflictIntervalTracker {
 public:
  enum class State { kNone, kSuspected, kConflict };
  ConflictIntervalTracker(int enter_frames, int exit_frames) : enter_(enter_frames), exit_(exit_frames) {}

  /// Feeds one frame; returns the state after it. A frame the detectors could not test (too few
  /// landmarks, no vision-only motion) and without evidence is no sign the conflict is over:
  /// it leaves the state and both runs as they are (an occluder filling the view must not count
  /// down the exit).
  State update(Timestamp t, bool evidence, bool tested = true);
  State state() const { return state_; }
  bool inConflict() const { return state_ == State::kConflict; }
  bool justEntered() const { return just_entered_; }
  bool justExited() const { return just_exited_; }
  /// Start of the current (or last) interval; 0 before the first.
  Timestamp intervalStart() const { return interval_start_; }
  void reset();

 private:
  int enter_, exit_;
  State state_ = State::kNone;
  int run_ = 0;           ///< consecutive frames with (outside) or without (inside) evidence
  Timestamp run_start_ = 0;
  Timestamp interval_start_ = 0;
  bool just_entered_ = false, just_exited_ = false;
};

}  // namespace mcvio::conflict
