#include "mcvio/sim/scenario_options.hpp"

#include "mcvio/core/input_error.hpp"

namespace mcvio::sim {

const char* toString(ScenarioKind kind) {
  switch (kind) {
    case ScenarioKind::kNone: return "none";
    case ScenarioKind::kElevator: return "elevator";
    case ScenarioKind::kVehicle: return "vehicle";
    case ScenarioKind::kSelfOcclusion: return "self_occlusion";
    case ScenarioKind::kPedestrian: return "pedestrian";
    case ScenarioKind::kSlowObject: return "slow_object";
  }
  return "none";
}

ScenarioKind scenarioKindFromString(const std::string& name) {
  for (ScenarioKind k : {ScenarioKind::kNone, ScenarioKind::kElevator, ScenarioKind::kVehicle,
                         ScenarioKind::kSelfOcclusion, ScenarioKind::kPedestrian,
                         ScenarioKind::kSlowObject})
    if (name == toString(k)) return k;
  throw InputError("scenario.kind: unknown scenario '" + name +
                   "' (none, elevator, vehicle, self_occlusion, pedestrian, slow_object)");
}

}  // namespace mcvio::sim
