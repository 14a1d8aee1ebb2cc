#include "rendered_frame_cache.hpp"

#include <stdexcept>
#include <string>

namespace mcvio::pipeline::sequences {

RenderedFrameCache::RenderedFrameCache(const sim::Simulator& simulator)
    : simulator_(simulator), frames_(simulator.frameTimes().size()) {}

OfflineInput RenderedFrameCache::input() {
  OfflineInput in;
  in.calibration = simulator_.calibration();
  in.imu = simulator_.imu();
  in.frame_times = simulator_.frameTimes();
  in.images = [this](std::size_t i) { return frame(i); };
  return in;
}

std::size_t RenderedFrameCache::rendered() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return rendered_;
}

std::pair<cv::Mat, cv::Mat> RenderedFrameCache::frame(std::size_t index) {
  if (index >= frames_.size())
    throw std::out_of_range("RenderedFrameCache: frame " + std::to_string(index) + " of " +
                            std::to_string(frames_.size()));
  // Rendering runs outside the lock; one run asks for a frame from one thread at a time.
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto& kept = frames_[index];
    if (!kept.first.empty()) return {kept.first.clone(), kept.second.clone()};
  }
  auto r = simulator_.renderFrame(index);
  std::pair<cv::Mat, cv::Mat> pair{r.cam0, r.cam1};
  const std::lock_guard<std::mutex> lock(mutex_);
  if (frames_[index].first.empty()) {
    frames_[index] = {pair.first.clone(), pair.second.clone()};
    ++rendered_;
  }
  return pair;
}

}  // namespace mcvio::pipeline::sequences
