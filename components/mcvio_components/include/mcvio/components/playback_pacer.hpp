#pragma once
#include <chrono>
#include <string>

#include "mcvio/core/time.hpp"

namespace mcvio::components {

/// When to publish each message of a paced pass, relative to the pass's start on the wall clock:
/// (t - t_first) / rate, except that a gap between consecutive messages longer than `max_gap_s`
/// counts as `max_gap_s` (a far-future stamp in a damaged bag, or a long pause in a recording,
/// would otherwise be slept through silently, for hours). Shared by both players.
class PlaybackPacer {
 public:
  struct Step {
    std::chrono::nanoseconds wall_offset{0};  ///< publish at pass start + this
    double gap_s = 0;                         ///< data time since the previous message
    double skipped_s = 0;                     ///< part of the gap not waited for (> 0: warn)
    bool backwards = false;                   ///< earlier than the previous message: played at once
  };
  /// `t_first` is where the pass starts in data time; `max_gap_s` <= 0 never skips.
  PlaybackPacer(Timestamp t_first, double rate, double max_gap_s);
  Step next(Timestamp t);
  /// What a player appends to "where" when a step was shortened or went backwards.
  static std::string describe(const Step& s, double max_gap_s);

 private:
  Timestamp origin_;
  Timestamp latest_;       // the newest stamp so far: gaps are measured from it
  Timestamp shift_ = 0;    // data time skipped so far
  double rate_;
  Timestamp max_gap_;      // 0: none
};

}  // namespace mcvio::components
