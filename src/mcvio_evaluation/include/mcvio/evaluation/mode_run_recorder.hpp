#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "mcvio/evaluation/benchmark_result.hpp"
#include "mcvio/estimator/estimator_options.hpp"

namespace mcvio::sim {
struct FeatureSequence;
}
namespace mcvio::estimator {
class SlidingWindowEstimator;
}

namespace mcvio::evaluation {

/// One resolution mode's estimator on a feature-level sequence, fed one frame at a time, and what
/// the benchmark keeps of its run (final and per-frame trajectories, detector log, CPU per frame).
/// The suite steps the recorders of all modes frame by frame in turn, so each mode's CPU per frame
/// is measured under the same host load: run one after the other, a busy minute on a shared
/// machine read as a mode's added cost.
class ModeRunRecorder {
 public:
  /// `sequence` must outlive the recorder. Throws mcvio::InputError on an unknown mode.
  ModeRunRecorder(const sim::FeatureSequence& sequence, const std::string& mode,
                  const estimator::EstimatorOptions& options, double pixel_sigma);
  ~ModeRunRecorder();
  ModeRunRecorder(ModeRunRecorder&&) noexcept;
  ModeRunRecorder& operator=(ModeRunRecorder&&) noexcept;

  /// Feeds the IMU up to frame `index` (in order, each frame once) and the frame itself.
  void addFrame(std::size_t index);
  /// The run so far; call once, after the last frame.
  BenchmarkModeRun finish();

  /// One recorder per mode over the whole sequence, the modes taking each frame in turn (the
  /// first one rotating from frame to frame); the runs in the order of `modes`.
  static std::vector<BenchmarkModeRun> runInTurn(const sim::FeatureSequence& sequence,
                                                 const std::vector<std::string>& modes,
                                                 const estimator::EstimatorOptions& options, double pixel_sigma);

 private:
  const sim::FeatureSequence* sequence_;
  std::unique_ptr<estimator::SlidingWindowEstimator> estimator_;
  BenchmarkModeRun run_;
  std::size_t next_imu_ = 0;
  std::vector<StampedPose> poses_, online_, secondary_;
  bool revised_ = false;
};

}  // namespace mcvio::evaluation
