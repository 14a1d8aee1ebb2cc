#pragma once
#include <cstdint>
#include <opencv2/core/types.hpp>
#include <string>
#include <vector>

#include "mcvio/core/feature_frame.hpp"

namespace mcvio::frontend {

/// Why a frame was or was not processed.
enum class FrameStatus : std::uint8_t {
  kOk = 0,
  kNoCalibration,  ///< no stereo calibration set yet
  kBadImage,       ///< empty, wrong encoding or wrong size
  kMissingRight,   ///< the right image is absent
  kOutOfOrder,     ///< timestamp not after the previous processed frame
};

const char* toString(FrameStatus status);

/// Recent left-image positions of one live track, oldest first (for drawing).
struct TrackHistory {
  std::uint64_t track_id = 0;
  TrackLabel label = TrackLabel::kUnknown;
  bool stereo = false;
  std::vector<cv::Point2f> positions;
};

/// Counters of one processed frame.
struct TrackingStats {
  int tracked = 0;         ///< tracks carried over from the previous frame
  int lost = 0;            ///< tracks dropped (KLT failure, forward-backward, out of image, into a mask)
  int detected = 0;        ///< new tracks
  int reidentified = 0;    ///< of the new tracks, lost ones recognised again (their old ids)
  int stereo_matched = 0;  ///< tracks with a right observation
  int consistent = 0;
  int inconsistent = 0;
  int imu_rejected = 0;          ///< IMU samples ignored: non-finite or not newer than the last
  bool gyro_prediction = false;  ///< initial flow came from the integrated gyro
  bool metric_check = false;     ///< the motion check used stereo points
  // CPU time of this thread per stage [ms]: what the frame cost, independent of machine load.
  double cpu_ms_prepare = 0;   ///< normalisation and pyramids
  double cpu_ms_temporal = 0;  ///< KLT between frames and the motion check
  double cpu_ms_detect = 0;
  double cpu_ms_stereo = 0;
  double cpu_ms_total = 0;
};

/// The frontend's answer for one input frame. When status != kOk, `features` is empty and the
/// tracker state is unchanged (IMU samples are still taken); `message` says what was wrong.
/// With kOk, a non-empty `message` is a warning (ignored IMU samples).
struct TrackingResult {
  FrameStatus status = FrameStatus::kOk;
  std::string message;
  FeatureFrame features;
  TrackingStats stats;
  bool ok() const { return status == FrameStatus::kOk; }
};

}  // namespace mcvio::frontend
