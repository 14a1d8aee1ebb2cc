#include "mcvio/conflict/conflict_interval_tracker.hpp"

#include <algorithm>
#include <cstddef>

namespace mcvio::conflict {

ConflictIntervalTracker::State ConflictIntervalTracker::update(Timestamp t, bool evidence, bool tested, double score,
                                                               bool persisted) {
  just_entered_ = just_exited_ = false;
  if (state_ != State::kConflict) {
    recent_.emplace_back(t, tested || evidence ? score : std::numeric_limits<double>::quiet_NaN());
    while (static_cast<int>(recent_.size()) > onset_lookback_ + enter_) recent_.pop_front();
  }
  if (!evidence && !tested) return state_;
  if (state_ != State::kConflict) {
    if (evidence) {
      if (run_ == 0) run_start_ = t;
      ++run_;
      if (persisted && run_ < enter_) {
        const std::size_t back = std::min(recent_.size(), static_cast<std::size_t>(std::max(1, enter_)));
        run_start_ = recent_[recent_.size() - back].first;
      }
      if (run_ >= enter_ || persisted) {
        state_ = State::kConflict;
        interval_start_ = run_start_;
        interval_onset_ = onsetBefore(run_start_);
        interval_end_ = 0;
        last_evidence_ = t;
        just_entered_ = true;
        run_ = 0;
        recent_.clear();
      } else {
        state_ = State::kSuspected;
      }
    } else {
      run_ = 0;
      state_ = State::kNone;
    }
    return state_;
  }
  if (evidence) last_evidence_ = t;
  run_ = evidence ? 0 : run_ + 1;
  quiet_run_ = !evidence && score < exit_quiet_score_ ? quiet_run_ + 1 : 0;  // NaN: not quiet
  if (run_ >= exit_ || (quiet_exit_allowed_ && exit_quiet_frames_ > 0 && quiet_run_ >= exit_quiet_frames_)) {
    state_ = State::kNone;
    interval_end_ = last_evidence_;
    just_exited_ = true;
    run_ = 0;
    quiet_run_ = 0;
  }
  return state_;
}

Timestamp ConflictIntervalTracker::onsetBefore(Timestamp start) const {
  // Back over the build-up: untested frames (NaN) neither extend nor end it on their own, the first
  // tested frame below the score ends it.
  Timestamp onset = start;
  int walked = 0;
  for (auto it = recent_.rbegin(); it != recent_.rend() && walked < onset_lookback_; ++it) {
    if (it->first >= start) continue;
    ++walked;
    if (std::isnan(it->second)) continue;
    if (it->second < onset_min_score_) break;
    onset = it->first;
  }
  return onset;
}

void ConflictIntervalTracker::reset() {
  state_ = State::kNone;
  run_ = 0;
  quiet_run_ = 0;
  just_entered_ = just_exited_ = false;
  recent_.clear();
}

}  // namespace mcvio::conflict
