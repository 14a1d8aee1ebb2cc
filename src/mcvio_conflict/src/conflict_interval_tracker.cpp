#include "mcvio/conflict/conflict_interval_tracker.hpp"

namespace mcvio::conflict {

ConflictIntervalTracker::State ConflictIntervalTracker::update(Timestamp t, bool evidence, bool tested) {
  just_entered_ = just_exited_ = false;
  if (!evidence && !tested) return state_;
  if (state_ != State::kConflict) {
    if (evidence) {
      if (run_ == 0) run_start_ = t;
      ++run_;
      if (run_ >= enter_) {
        state_ = State::kConflict;
        interval_start_ = run_start_;
        just_entered_ = true;
        run_ = 0;
      } else {
        state_ = State::kSuspected;
      }
    } else {
      run_ = 0;
      state_ = State::kNone;
    }
    return state_;
  }
  run_ = evidence ? 0 : run_ + 1;
  if (run_ >= exit_) {
    state_ = State::kNone;
    just_exited_ = true;
    run_ = 0;
  }
  return state_;
}

void ConflictIntervalTracker::reset() {
  state_ = State::kNone;
  run_ = 0;
  just_entered_ = just_exited_ = false;
}

}  // namespace mcvio::conflict
