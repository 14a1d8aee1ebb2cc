#pragma once
#include <Eigen/Core>

#include "mcvio/core/time.hpp"

namespace mcvio::sim {

/// Smooth point-to-point translation of a moving frame (an elevator cabin, a vehicle, a walking
/// person): at rest before `start`, travels `travel` metres along `direction` during `duration`,
/// at rest afterwards. Displacement s(u) = L (u - sin(2 pi u) / (2 pi)), u = (t - start) / duration,
/// so velocity and acceleration are zero at both ends and the peak speed is 2 L / duration.
class RideProfile {
 public:
  RideProfile() = default;
  RideProfile(Timestamp start, Timestamp duration, const Eigen::Vector3d& direction, double travel);

  Eigen::Vector3d displacement(Timestamp t) const;
  Eigen::Vector3d velocity(Timestamp t) const;
  Eigen::Vector3d acceleration(Timestamp t) const;
  /// True strictly inside the ride, where the frame moves.
  bool moving(Timestamp t) const { return duration_ > 0 && t > start_ && t < start_ + duration_; }
  Timestamp start() const { return start_; }
  Timestamp end() const { return start_ + duration_; }

 private:
  double phase(Timestamp t) const;
  Timestamp start_ = 0;
  Timestamp duration_ = 0;
  Eigen::Vector3d direction_ = Eigen::Vector3d::UnitZ();
  double travel_ = 0.0;
};

}  // namespace mcvio::sim
