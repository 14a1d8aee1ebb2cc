#include "mcvio/evaluation/mode_run_recorder.hpp"

#include <chrono>

#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/estimator/sliding_window_estimator.hpp"
#include "mcvio/sim/feature_simulator.hpp"

namespace mcvio::evaluation {

namespace {

DetectorRecord::State toRecordState(estimator::ConflictReport::State s) {
  switch (s) {
    case estimator::ConflictReport::State::kSuspected: return DetectorRecord::State::kSuspected;
    case estimator::ConflictReport::State::kConflict: return DetectorRecord::State::kConflict;
    default: return DetectorRecord::State::kNone;
  }
}

}  // namespace

ModeRunRecorder::ModeRunRecorder(const sim::FeatureSequence& sequence, const std::string& mode,
                                 const estimator::EstimatorOptions& options, double pixel_sigma)
    : sequence_(&sequence) {
  estimator::EstimatorOptions eo = options;
  eo.observation_sigma_px = pixel_sigma;
  eo.conflict.mode = conflict::resolutionModeFromString(mode, "mode");
  estimator_ = std::make_unique<estimator::SlidingWindowEstimator>(eo, sequence.calibration);
  run_.mode = mode;
  poses_.reserve(sequence.frames.size());
  online_.reserve(sequence.frames.size());
}

ModeRunRecorder::~ModeRunRecorder() = default;
ModeRunRecorder::ModeRunRecorder(ModeRunRecorder&&) noexcept = default;
ModeRunRecorder& ModeRunRecorder::operator=(ModeRunRecorder&&) noexcept = default;

void ModeRunRecorder::addFrame(std::size_t index) {
  const auto t0 = std::chrono::steady_clock::now();
  const sim::FeatureSequence& seq = *sequence_;
  const auto& f = seq.frames[index];
  while (next_imu_ < seq.imu.size() && seq.imu[next_imu_].t <= f.t) estimator_->addImu(seq.imu[next_imu_++]);
  const estimator::EstimatorOutput out = estimator_->addFrame(f);
  ++run_.frames;
  run_.wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!out.frame_accepted || out.status != estimator::EstimatorStatus::kTracking) return;
  if (!poses_.empty() && out.t <= poses_.back().t) return;
  poses_.push_back({out.t, out.p_WB, out.q_WB.normalized()});
  online_.push_back(poses_.back());
  if (out.conflict.secondary_valid) secondary_.push_back({out.t, out.conflict.p_WS, out.conflict.q_WS.normalized()});
  // The conflict window re-estimated earlier frames (and the conflicting frame seen from them):
  // the run's trajectories are the final estimates.
  estimator::applyPoseRevisions(&poses_, out.revised_poses);
  revised_ = revised_ || !out.revised_poses.empty();
  estimator::applyPoseRevisions(&secondary_, out.revised_secondary);
  run_.cpu_ms.push_back(out.timings.cpu_total_ms);
  run_.conflict_ms.push_back(out.timings.conflict_ms);
  DetectorRecord r;
  r.t = out.t;
  r.state = toRecordState(out.conflict.state);
  r.propagated_chi2 = out.conflict.propagated_chi2;
  r.propagated_threshold = out.conflict.propagated_threshold;
  r.landmarks_tested = out.conflict.landmarks_tested;
  r.landmarks_inconsistent = out.conflict.landmarks_inconsistent;
  r.inconsistent_fraction = out.conflict.inconsistent_fraction;
  r.coherence = out.conflict.coherence;
  r.interval_start = out.conflict.interval_start;
  r.interval_onset = out.conflict.interval_onset;
  r.interval_end = out.conflict.interval_end;
  r.resolution_mode = out.conflict.resolution_mode;
  r.evidence_score = out.conflict.evidence_score;
  run_.detector.push_back(r);
}

BenchmarkModeRun ModeRunRecorder::finish() {
  run_.resets = estimator_->resetCount();
  run_.estimate = Trajectory(std::move(poses_), run_.mode);
  if (revised_) run_.estimate_online = Trajectory(std::move(online_), run_.mode + " online");
  run_.secondary = Trajectory(std::move(secondary_), run_.mode + " secondary");
  return std::move(run_);
}

std::vector<BenchmarkModeRun> ModeRunRecorder::runInTurn(const sim::FeatureSequence& sequence,
                                                         const std::vector<std::string>& modes,
                                                         const estimator::EstimatorOptions& options, double pixel_sigma) {
  std::vector<ModeRunRecorder> recorders;
  recorders.reserve(modes.size());
  for (const auto& mode : modes) recorders.emplace_back(sequence, mode, options, pixel_sigma);
  const std::size_t n = recorders.size();
  for (std::size_t i = 0; i < sequence.frames.size(); ++i)
    for (std::size_t j = 0; j < n; ++j) recorders[(i + j) % n].addFrame(i);
  std::vector<BenchmarkModeRun> runs;
  runs.reserve(n);
  for (auto& recorder : recorders) runs.push_back(recorder.finish());
  return runs;
}

}  // namespace mcvio::evaluation
