#pragma once
#include <limits>
#include <string>

#include "mcvio/core/time.hpp"

namespace mcvio::evaluation {

/// One frame of a run's motion-conflict detector output (one row of OUT/conflict.csv).
/// Columns a file lacks stay NaN (numbers), -1 (counts) or empty.
struct DetectorRecord {
  enum class State { kNone, kSuspected, kConflict };
  Timestamp t = 0;
  State state = State::kNone;
  double propagated_chi2 = std::numeric_limits<double>::quiet_NaN();
  double propagated_threshold = std::numeric_limits<double>::quiet_NaN();
  int landmarks_tested = -1;
  int landmarks_inconsistent = -1;
  double inconsistent_fraction = std::numeric_limits<double>::quiet_NaN();
  double coherence = std::numeric_limits<double>::quiet_NaN();
  Timestamp interval_start = 0;
  /// The interval in hindsight [m-, m+] (see ConflictIntervalTracker): its onset, and its end once
  /// it has closed (0 while open). 0 when the file lacks the columns.
  Timestamp interval_onset = 0;
  Timestamp interval_end = 0;
  std::string resolution_mode;
  /// The detectors' combined evidence score (their statistics relative to their thresholds, at
  /// least 1 on a frame with evidence); NaN where nothing could be tested or the file lacks it.
  double evidence_score = std::numeric_limits<double>::quiet_NaN();

  /// propagated_chi2 / propagated_threshold (> 1 means the chi-square test fails); the bare
  /// chi2 when the threshold is missing or not positive.
  double propagatedRatio() const {
    return propagated_threshold > 0 ? propagated_chi2 / propagated_threshold : propagated_chi2;
  }
};

/// "none", "suspected", "conflict".
const char* toString(DetectorRecord::State state);

}  // namespace mcvio::evaluation
