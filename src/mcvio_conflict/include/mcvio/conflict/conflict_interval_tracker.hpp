#pragma once
#include <cmath>
#include <deque>
#include <limits>
#include <utility>

#include "mcvio/core/time.hpp"

namespace mcvio::conflict {

/// Turns per-frame evidence into conflict intervals [m-, m+] with hysteresis: an interval opens
/// after `enter_frames` consecutive frames with evidence and closes after `exit_frames`
/// consecutive frames without. Its detected start is the first frame of the evidence run, so a
/// resolution can act from there.
///
/// The hysteresis delays both decisions, and a conflict that builds up gently (a cabin starting,
/// a pedestrian walking into view) moves the detector statistics long before they reach their
/// thresholds. So the tracker also keeps the interval's bounds in hindsight: its onset m- goes
/// back from the detected start over the frames whose evidence score (the statistics relative to
/// their thresholds, 1 = the detector fires) stayed at least `onset_min_score`, and its end m+ is
/// the last frame with evidence before the exit run.
///
/// A conflict that has plainly ended needs less confirmation than one hovering at its thresholds:
/// `exit_quiet_frames` consecutive clean frames whose score stays under `exit_quiet_score` close
/// the interval before `exit_frames` (0: off), where the caller allows it. A vehicle that has
/// stopped drops its score from 1 to a third within three frames; a cabin braking gently lingers
/// over a half.
class ConflictIntervalTracker {
 public:
  enum class State { kNone, kSuspected, kConflict };
  ConflictIntervalTracker(int enter_frames, int exit_frames, double onset_min_score = 0.1,
                          int onset_lookback_frames = 60, int exit_quiet_frames = 0, double exit_quiet_score = 0.0)
      : enter_(enter_frames), exit_(exit_frames), onset_min_score_(onset_min_score),
        onset_lookback_(onset_lookback_frames), exit_quiet_frames_(exit_quiet_frames),
        exit_quiet_score_(exit_quiet_score) {}

  /// Feeds one frame; returns the state after it. A frame the detectors could not test (too few
  /// landmarks, no vision-only motion) and without evidence is no sign the conflict is over:
  /// it leaves the state and both runs as they are (an occluder filling the view must not count
  /// down the exit). `score` is the frame's evidence strength (NaN: not tested). `persisted`:
  /// the evidence's detector has itself seen it on at least `enter_frames` consecutive frames (a
  /// run of its own, not one this tracker counted), so the interval opens on this frame, started
  /// `enter_frames` - 1 frames back as if this tracker had counted that run.
  State update(Timestamp t, bool evidence, bool tested = true,
               double score = std::numeric_limits<double>::quiet_NaN(), bool persisted = false);
  /// Whether a quiet run may close the interval (default: yes). The caller knows which conflicts
  /// end for good once quiet: see ConflictOptions::exit_quiet_frames.
  void setQuietExitAllowed(bool allowed) { quiet_exit_allowed_ = allowed; }
  State state() const { return state_; }
  bool inConflict() const { return state_ == State::kConflict; }
  bool justEntered() const { return just_entered_; }
  bool justExited() const { return just_exited_; }
  /// Detected start of the current (or last) interval; 0 before the first.
  Timestamp intervalStart() const { return interval_start_; }
  /// Onset m- of the current (or last) interval in hindsight (<= intervalStart()); 0 before the first.
  Timestamp intervalOnset() const { return interval_onset_; }
  /// End m+ of the last interval (its last frame with evidence) once it has closed; 0 while it is
  /// open or before the first.
  Timestamp intervalEnd() const { return interval_end_; }
  void reset();

 private:
  Timestamp onsetBefore(Timestamp start) const;
  int enter_, exit_;
  double onset_min_score_;
  int onset_lookback_;
  int exit_quiet_frames_;
  double exit_quiet_score_;
  State state_ = State::kNone;
  int run_ = 0;           ///< consecutive frames with (outside) or without (inside) evidence
  int quiet_run_ = 0;     ///< inside: consecutive clean frames scoring under exit_quiet_score
  Timestamp run_start_ = 0;
  Timestamp interval_start_ = 0;
  Timestamp interval_onset_ = 0, interval_end_ = 0, last_evidence_ = 0;
  std::deque<std::pair<Timestamp, double>> recent_;  ///< (t, score) of the frames outside an interval
  bool just_entered_ = false, just_exited_ = false;
  bool quiet_exit_allowed_ = true;
};

}  // namespace mcvio::conflict
