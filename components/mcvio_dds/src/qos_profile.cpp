#include "mcvio/dds/qos_profile.hpp"

namespace mcvio::dds {

std::string QosProfile::toRosbag2Yaml() const {
  // rosbag2 numbers: history 1 keep_last / 2 keep_all, reliability 1 reliable / 2 best_effort,
  // durability 1 transient_local / 2 volatile; durations left at "infinite" (0 = default).
  std::string y;
  y += "history: " + std::string(history == History::kKeepLast ? "1" : "2") + "\n";
  y += "  depth: " + std::to_string(depth) + "\n";
  y += "  reliability: " + std::string(reliability == Reliability::kReliable ? "1" : "2") + "\n";
  y += "  durability: " + std::string(durability == Durability::kTransientLocal ? "1" : "2") + "\n";
  y += "  deadline:\n    sec: 9223372036\n    nsec: 854775807\n";
  y += "  lifespan:\n    sec: 9223372036\n    nsec: 854775807\n";
  y += "  liveliness: 1\n";
  y += "  liveliness_lease_duration:\n    sec: 9223372036\n    nsec: 854775807\n";
  y += std::string("  avoid_ros_namespace_conventions: ") + (avoid_ros_namespace_conventions ? "true" : "false") + "\n";
  return y;
}

std::string QosProfile::describe() const {
  std::string s = reliability == Reliability::kReliable ? "reliable" : "best_effort";
  s += durability == Durability::kTransientLocal ? ", transient_local" : ", volatile";
  s += history == History::kKeepAll ? ", keep_all" : ", keep_last(" + std::to_string(depth) + ")";
  return s;
}

}  // namespace mcvio::dds
