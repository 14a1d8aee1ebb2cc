#include "mcvio/sim/frame_riding_trajectory.hpp"

namespace mcvio::sim {

FrameRidingTrajectory::FrameRidingTrajectory(std::shared_ptr<const Trajectory> in_frame,
                                             RideProfile ride)
    : in_frame_(std::move(in_frame)), ride_(ride) {}

KinematicState FrameRidingTrajectory::evaluate(Timestamp t) const {
  // The frame only translates, so positions and their derivatives simply add.
  KinematicState s = in_frame_->evaluate(t);
  s.p_wb += ride_.displacement(t);
  s.v_w += ride_.velocity(t);
  s.a_w += ride_.acceleration(t);
  return s;
}

}  // namespace mcvio::sim
