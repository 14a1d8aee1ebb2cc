#pragma once
#include <opencv2/core/mat.hpp>
#include <vector>

#include "mcvio/frontend/tracking_result.hpp"

namespace mcvio::frontend {

/// Draws tracks over an image for RViz/Foxglove: a polyline through each track's recent
/// positions and a dot at its current one, all outlined in black; green = consistent,
/// red = inconsistent, yellow = not yet judged; filled dot = stereo-matched, ring = left only.
/// @param image mono8 or 3-channel RGB; @return rgb8 (CV_8UC3, R first) of the same size.
/// @param mask optional mono8 of the image's size (FeatureTracker::mask): its non-zero pixels,
/// where no feature is tracked, are drawn darker.
/// Throws mcvio::InputError for other image types or a mask of another size.
cv::Mat drawTracks(const cv::Mat& image, const std::vector<TrackHistory>& tracks, const cv::Mat& mask = cv::Mat());

}  // namespace mcvio::frontend
