#pragma once
#include <string>

namespace mcvio::dds::bench {

/// ROS topic of the wrapper's ping/pong ("/dds_bench/image/ping" is DDS topic
/// "rt/dds_bench/image/ping").
inline std::string wrapperTopic(const std::string& type_key, const std::string& leg) {
  return "/dds_bench/" + type_key + "/" + leg;
}
/// DDS topic of the bare endpoints: a different name, so wrapper and bare never match each other.
inline std::string bareTopic(const std::string& type_key, const std::string& leg) {
  return "dds_bench_bare/" + type_key + "/" + leg;
}

}  // namespace mcvio::dds::bench
