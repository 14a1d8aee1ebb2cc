#pragma once
#include <string>

#include "mcvio/core/time.hpp"

namespace mcvio::dataset {

/// One stereo pair listed by a data set: timestamps and absolute image paths. The images are
/// loaded on demand (EurocDataset::loadImage) so a long sequence does not sit in memory.
struct StereoFrame {
  Timestamp t = 0;       ///< cam0 timestamp: the frame's time
  Timestamp t_cam1 = 0;  ///< cam1 timestamp (equal to t in EuRoC)
  std::string cam0_path;
  std::string cam1_path;

  const std::string& path(int camera) const { return camera == 0 ? cam0_path : cam1_path; }
};

}  // namespace mcvio::dataset
