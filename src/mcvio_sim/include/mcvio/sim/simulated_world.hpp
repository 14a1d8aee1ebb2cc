#pragma once
#include <memory>
#include <string>
#include <vector>

#include "mcvio/sim/ride_profile.hpp"
#include "mcvio/sim/scene.hpp"
#include "mcvio/sim/trajectory.hpp"

namespace mcvio::sim {

/// A scenario made concrete: the scene, the device's world trajectory and which bodies carry the
/// conflicting motion.
struct SimulatedWorld {
  Scene scene;
  /// Device (IMU/body) trajectory in the inertial world, including any ride.
  std::shared_ptr<const Trajectory> trajectory;
  /// The device's trajectory relative to the frame it rides (equal to `trajectory` when it
  /// rides nothing).
  std::shared_ptr<const Trajectory> trajectory_in_frame;
  /// The ride the device is carried on (elevator, vehicle), if any: its acceleration is what the
  /// IMU feels in addition to the in-frame motion.
  bool device_rides = false;
  RideProfile device_ride;
  std::string motion_name = "none";  ///< label written to conflict_labels.csv
  std::vector<int> conflict_bodies;  ///< bodies whose motion conflicts with the inertial world
};

}  // namespace mcvio::sim
