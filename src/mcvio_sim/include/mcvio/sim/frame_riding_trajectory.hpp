#pragma once
#include <memory>

#include "mcvio/sim/ride_profile.hpp"
#include "mcvio/sim/trajectory.hpp"

namespace mcvio::sim {

/// A device carried inside a translating frame (elevator cabin, vehicle): the device moves along
/// `in_frame` relative to the frame while the frame itself follows `ride`. The IMU feels both
/// motions; a camera looking at the frame's interior sees only `in_frame`.
class FrameRidingTrajectory : public Trajectory {
 public:
  FrameRidingTrajectory(std::shared_ptr<const Trajectory> in_frame, RideProfile ride);

  KinematicState evaluate(Timestamp t) const override;
  Timestamp startTime() const override { return in_frame_->startTime(); }
  Timestamp endTime() const override { return in_frame_->endTime(); }

 private:
  std::shared_ptr<const Trajectory> in_frame_;
  RideProfile ride_;
};

}  // namespace mcvio::sim
