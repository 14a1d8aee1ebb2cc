#pragma once
#include <string>

namespace mcvio::sim {

/// Which motion conflict the simulated sequence contains.
enum class ScenarioKind {
  kNone,           ///< a static textured office with a corridor
  kElevator,       ///< the device rides a closed cabin vertically; only the IMU feels the ride
  kVehicle,        ///< the device rides a vehicle; the interior moves with it, the street is static
  kSelfOcclusion,  ///< a laptop carried in front of the cameras covers most of the view
  kPedestrian,     ///< a person-sized object walks across the view
  kSlowObject,     ///< a large object drifts slowly through the view
};

/// "none", "elevator", "vehicle", "self_occlusion", "pedestrian", "slow_object".
const char* toString(ScenarioKind kind);
/// Inverse of toString(); throws mcvio::InputError naming the value otherwise.
ScenarioKind scenarioKindFromString(const std::string& name);

/// When and how strongly the conflicting motion appears.
struct ScenarioOptions {
  ScenarioKind kind = ScenarioKind::kNone;
  double onset_s = 20.0;     ///< start of the conflicting motion, seconds after the first frame
  double duration_s = 15.0;  ///< how long it lasts [s]
  /// Intended fraction of the image the conflicting motion covers, in (0, 1]. It sizes windows
  /// (elevator, vehicle), the laptop, and the distance/size of the moving objects; the labels
  /// report the fraction actually rendered.
  double coverage = 0.7;
  /// Distance the moving frame or object travels [m]; 0 = scenario default (elevator 12 m,
  /// vehicle 4 m/s * duration, pedestrian across the view, slow object 0.08 m/s * duration).
  double travel_m = 0.0;
};

}  // namespace mcvio::sim
