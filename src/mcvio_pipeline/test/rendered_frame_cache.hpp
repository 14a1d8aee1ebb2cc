#pragma once
#include <cstddef>
#include <mutex>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "mcvio/pipeline/offline_run.hpp"
#include "mcvio/sim/simulator.hpp"

namespace mcvio::pipeline::sequences {

/// The stereo pairs of a rendered sequence, each rendered on first use and kept, so the tests that
/// run one sequence two or three times (a mode against another, an option against the shipped
/// value) render it once: rendering is about two thirds of such a run's CPU time. A 30 s sequence
/// holds ~430 MB.
class RenderedFrameCache {
 public:
  explicit RenderedFrameCache(const sim::Simulator& simulator);

  const sim::Simulator& simulator() const { return simulator_; }

  /// runOffline() input over the cached pairs. Each call hands out copies, so a run that draws on
  /// its images cannot change what the next run gets. The cache must outlive the run.
  OfflineInput input();

  /// Pairs rendered so far (a run renders each at most once).
  std::size_t rendered() const;

 private:
  std::pair<cv::Mat, cv::Mat> frame(std::size_t index);

  const sim::Simulator& simulator_;
  mutable std::mutex mutex_;
  std::vector<std::pair<cv::Mat, cv::Mat>> frames_;  ///< empty until rendered
  std::size_t rendered_ = 0;
};

}  // namespace mcvio::pipeline::sequences
