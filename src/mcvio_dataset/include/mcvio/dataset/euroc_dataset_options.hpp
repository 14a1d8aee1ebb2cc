#pragma once
#include "mcvio/core/time.hpp"

namespace YAML {
class Node;
}

namespace mcvio::dataset {

/// How EurocDataset::open treats imperfect input. YAML keys are the member names.
struct EurocDatasetOptions {
  /// false: a malformed CSV row (wrong column count, not a number, NaN/inf, time not increasing)
  /// throws mcvio::InputError naming file and line. true: the row is skipped and reported in
  /// EurocDataset::warnings(), so a sequence with a few damaged rows stays usable.
  bool skip_bad_rows = false;
  /// cam0 and cam1 images pair when their timestamps differ by at most this much [ns]
  /// (EuRoC's are identical).
  Timestamp max_stereo_offset_ns = 0;
  /// Compare the first image of each camera (PNG header only) against sensor.yaml's
  /// resolution at open(); loadImage() always checks the image it loads.
  bool check_image_size = true;

  /// Reads the keys present in `node` (absent keys keep their defaults); throws
  /// mcvio::InputError naming the key on a wrong type or a negative offset.
  static EurocDatasetOptions fromYaml(const YAML::Node& node);
};

}  // namespace mcvio::dataset
