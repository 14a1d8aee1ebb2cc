#pragma once
#include <opencv2/core/mat.hpp>
#include <vector>

#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/time.hpp"

namespace mcvio::frontend {

/// One stereo frame handed to the frontend, with the IMU samples received since the previous
/// frame (they may overlap earlier batches; older or repeated samples are ignored).
struct StereoInput {
  Timestamp t = 0;  ///< left image time [ns]
  cv::Mat left;     ///< mono8 (CV_8UC1), calibrated resolution
  cv::Mat right;    ///< mono8 (CV_8UC1), same time as left; empty = missing
  std::vector<ImuSample> imu;
};

}  // namespace mcvio::frontend
