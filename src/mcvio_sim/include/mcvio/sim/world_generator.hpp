#pragma once
#include <cstdint>
#include <memory>

#include "mcvio/core/camera_calibration.hpp"
#include "mcvio/sim/scenario_options.hpp"
#include "mcvio/sim/simulated_world.hpp"

namespace mcvio::sim {

/// Builds the world of a scenario around a device trajectory: an office with a corridor, boxes
/// and wall panels (none, self_occlusion, pedestrian, slow_object), an elevator cabin in its shaft,
/// or a vehicle on a street, plus the conflicting body. Deterministic for a seed.
class WorldGenerator {
 public:
  struct Inputs {
    ScenarioOptions scenario;
    Timestamp start = 0;  ///< first frame time; scenario onset is relative to it
    Timestamp end = 0;
    std::uint64_t seed = 1;
    CameraCalibration cam0;  ///< places the carried laptop in front of the left camera
    /// Semi-real mode: the recorded device trajectory, relative to the riding frame for elevator
    /// and vehicle. Null: a synthetic trajectory suited to the scenario.
    std::shared_ptr<const Trajectory> recorded;
    int texture_size = 1024;  ///< texels per texture edge (power of two)
  };

  static SimulatedWorld generate(const Inputs& inputs);
};

}  // namespace mcvio::sim
