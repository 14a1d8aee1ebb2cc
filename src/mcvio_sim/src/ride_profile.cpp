#include "mcvio/sim/ride_profile.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mcvio::sim {

RideProfile::RideProfile(Timestamp start, Timestamp duration, const Eigen::Vector3d& direction,
                         double travel)
    : start_(start), duration_(duration), direction_(direction.normalized()), travel_(travel) {
  if (duration < 0) throw std::invalid_argument("RideProfile: negative duration");
}

double RideProfile::phase(Timestamp t) const {
  if (duration_ <= 0) return t >= start_ ? 1.0 : 0.0;
  return std::clamp(toSeconds(t - start_) / toSeconds(duration_), 0.0, 1.0);
}

Eigen::Vector3d RideProfile::displacement(Timestamp t) const {
  const double u = phase(t);
  return direction_ * travel_ * (u - std::sin(2.0 * M_PI * u) / (2.0 * M_PI));
}

Eigen::Vector3d RideProfile::velocity(Timestamp t) const {
  if (!moving(t)) return Eigen::Vector3d::Zero();
  const double d = toSeconds(duration_);
  return direction_ * (travel_ / d * (1.0 - std::cos(2.0 * M_PI * phase(t))));
}

Eigen::Vector3d RideProfile::acceleration(Timestamp t) const {
  if (!moving(t)) return Eigen::Vector3d::Zero();
  const double d = toSeconds(duration_);
  return direction_ * (travel_ / (d * d) * 2.0 * M_PI * std::sin(2.0 * M_PI * phase(t)));
}

}  // namespace mcvio::sim
