#pragma once
#include <string>

#include "mcvio/core/time.hpp"

namespace mcvio::dataset {

/// Ground-truth motion-conflict label of one camera frame, one row of mav0/conflict_labels.csv:
///   #timestamp [ns],in_conflict,motion,covered_fraction
///   1403715273262142976,1,elevator,0.85
struct ConflictLabel {
  Timestamp t = 0;
  bool in_conflict = false;
  /// Name of the secondary motion ("none", "elevator", "vehicle", ...): no commas, quotes or
  /// line breaks, since it is a bare CSV field.
  std::string motion = "none";
  /// Fraction of the image area covered by the conflicting motion, in [0, 1].
  double covered_fraction = 0.0;
};

}  // namespace mcvio::dataset
