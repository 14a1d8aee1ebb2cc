#include "mcvio/components/playback_pacer.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>

namespace mcvio::components {

PlaybackPacer::PlaybackPacer(Timestamp t_first, double rate, double max_gap_s)
    : origin_(t_first),
      latest_(t_first),
      rate_(rate),
      // Beyond ~30 years no gap is skipped anyway; this also keeps +inf out of fromSeconds().
      max_gap_(max_gap_s > 0 && max_gap_s < 1e9 ? fromSeconds(max_gap_s) : 0) {}

PlaybackPacer::Step PlaybackPacer::next(Timestamp t) {
  Step s;
  if (t < latest_) {
    // Kept on the newest message's schedule (already due), so it goes out at once and the next
    // message's gap is still measured from the newest stamp.
    s.backwards = true;
    s.gap_s = toSeconds(t - latest_);
  } else {
    const Timestamp gap = t - latest_;
    s.gap_s = toSeconds(gap);
    if (max_gap_ > 0 && gap > max_gap_) {
      shift_ += gap - max_gap_;
      s.skipped_s = toSeconds(gap - max_gap_);
    }
    latest_ = t;
  }
  // Clamped: converting an out-of-range double to an integer is undefined (1e17 ns is 3 years).
  const double offset_ns = static_cast<double>(latest_ - origin_ - shift_) / rate_;
  s.wall_offset = std::chrono::nanoseconds(static_cast<std::int64_t>(std::clamp(offset_ns, 0.0, 1e17)));
  return s;
}

std::string PlaybackPacer::describe(const Step& s, double max_gap_s) {
  char text[200];
  if (s.backwards) {
    std::snprintf(text, sizeof text, "stamp %.3f s before the previous message's; played at once", -s.gap_s);
  } else {
    std::snprintf(text, sizeof text,
                  "%.3f s after the previous message, more than the max gap of %g s: played %g s after it instead",
                  s.gap_s, max_gap_s, max_gap_s);
  }
  return text;
}

}  // namespace mcvio::components
