#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "mcvio/core/time.hpp"

namespace mcvio {

/// How the frontend's geometric check judged a track in this frame.
enum class TrackLabel : std::uint8_t { kUnknown = 0, kConsistent = 1, kInconsistent = 2 };

/// One tracked feature seen by one camera in one frame (mirrors mcvio_msgs/Feature).
struct FeatureObservation {
  std::uint64_t track_id = 0;
  std::uint8_t camera_index = 0;         ///< 0 = cam0 (left), 1 = cam1 (right)
  Eigen::Vector2d pixel{0, 0};           ///< distorted pixel coordinates [px]
  Eigen::Vector2d normalized{0, 0};      ///< undistorted normalised coordinates (x/z, y/z)
  TrackLabel label = TrackLabel::kUnknown;
};

/// The frontend's output for one stereo frame: the contract between frontend and backend
/// (mirrors mcvio_msgs/FeatureFrame).
struct FeatureFrame {
  Timestamp t = 0;
  std::uint32_t frame_index = 0;
  std::vector<FeatureObservation> features;
};

}  // namespace mcvio
