#include "mcvio/frontend/track_drawer.hpp"

#include <opencv2/imgproc.hpp>

#include "mcvio/core/input_error.hpp"

namespace mcvio::frontend {

cv::Mat drawTracks(const cv::Mat& image, const std::vector<TrackHistory>& tracks, const cv::Mat& mask) {
  cv::Mat rgb;
  if (image.type() == CV_8UC1) {
    cv::cvtColor(image, rgb, cv::COLOR_GRAY2RGB);
  } else if (image.type() == CV_8UC3) {
    rgb = image.clone();
  } else {
    throw InputError("drawTracks: image must be mono8 or rgb8, got " +
                     cv::typeToString(image.type()));
  }
  if (!mask.empty()) {
    if (mask.type() != CV_8UC1 || mask.size() != image.size())
      throw InputError("drawTracks: the mask must be mono8 of the image's size, got " + std::to_string(mask.cols) + "x" +
                       std::to_string(mask.rows) + " " + cv::typeToString(mask.type()));
    cv::Mat dark;
    rgb.convertTo(dark, -1, 0.35);
    dark.copyTo(rgb, mask);
  }
  // A dark outline under every line and dot first, then the colours on top: without it thin
  // green, yellow and ring marks vanish on bright or busy texture.
  const cv::Scalar outline(0, 0, 0);
  for (const TrackHistory& t : tracks) {
    for (std::size_t i = 1; i < t.positions.size(); ++i) {
      cv::line(rgb, t.positions[i - 1], t.positions[i], outline, 3, cv::LINE_AA);
    }
    if (!t.positions.empty()) {
      cv::circle(rgb, t.positions.back(), t.stereo ? 4 : 3, outline, t.stereo ? -1 : 3,
                 cv::LINE_AA);
    }
  }
  for (const TrackHistory& t : tracks) {
    // Colours are in RGB order because the output is rgb8.
    cv::Scalar colour(255, 210, 0);
    if (t.label == TrackLabel::kConsistent) colour = cv::Scalar(0, 220, 0);
    if (t.label == TrackLabel::kInconsistent) colour = cv::Scalar(255, 0, 0);
    for (std::size_t i = 1; i < t.positions.size(); ++i) {
      cv::line(rgb, t.positions[i - 1], t.positions[i], colour, 1, cv::LINE_AA);
    }
    if (!t.positions.empty()) {
      cv::circle(rgb, t.positions.back(), 3, colour, t.stereo ? -1 : 1, cv::LINE_AA);
    }
  }
  return rgb;
}

}  // namespace mcvio::frontend
