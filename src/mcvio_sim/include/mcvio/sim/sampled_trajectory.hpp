#pragma once
#include <vector>

#include "mcvio/dataset/ground_truth_state.hpp"
#include "mcvio/sim/trajectory.hpp"

namespace mcvio::sim {

/// A trajectory interpolated from recorded ground-truth poses (semi-real mode): linear in
/// position and velocity, slerp in orientation; acceleration and angular rate are the finite
/// differences of the bracketing samples. Good for rendering along a real path, not for
/// synthesising an IMU (semi-real mode keeps the real IMU).
class SampledTrajectory : public Trajectory {
 public:
  /// Samples must be strictly increasing in time (at least two); throws std::invalid_argument.
  explicit SampledTrajectory(std::vector<dataset::GroundTruthState> samples);

  KinematicState evaluate(Timestamp t) const override;
  Timestamp startTime() const override { return samples_.front().t; }
  Timestamp endTime() const override { return samples_.back().t; }
  const std::vector<dataset::GroundTruthState>& samples() const { return samples_; }

 private:
  std::vector<dataset::GroundTruthState> samples_;
};

}  // namespace mcvio::sim
