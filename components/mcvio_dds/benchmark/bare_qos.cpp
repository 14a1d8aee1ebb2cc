#include "bare_qos.hpp"

#include <stdexcept>

#include "mcvio/dds/fastdds_qos.hpp"

namespace mcvio::dds::bench {

using namespace eprosima::fastdds::dds;

namespace {

template <class Qos>
void apply(Qos& qos, BareProfile profile) {
  qos.reliability().kind = RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = VOLATILE_DURABILITY_QOS;
  if (profile == BareProfile::kLossless) {
    qos.history().kind = KEEP_ALL_HISTORY_QOS;
    qos.history().depth = 1;
    qos.resource_limits().max_samples = 100;
    qos.resource_limits().max_instances = 1;
    qos.resource_limits().max_samples_per_instance = 100;
  } else {
    qos.history().kind = KEEP_LAST_HISTORY_QOS;
    qos.history().depth = 10;
  }
  qos.endpoint().history_memory_policy =
      eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
}

QosProfile presetOf(BareProfile profile) {
  return profile == BareProfile::kLossless ? QosProfile::lossless() : QosProfile::defaults();
}

}  // namespace

DataWriterQos bareWriterQos(BareProfile profile) {
  DataWriterQos qos = DATAWRITER_QOS_DEFAULT;
  apply(qos, profile);
  if (profile == BareProfile::kLossless)
    qos.reliability().max_blocking_time = eprosima::fastrtps::Duration_t(1, 0);
  return qos;
}

DataReaderQos bareReaderQos(BareProfile profile) {
  DataReaderQos qos = DATAREADER_QOS_DEFAULT;
  apply(qos, profile);
  return qos;
}

void checkBareQosMatchesWrapper() {
  for (BareProfile profile : {BareProfile::kLossless, BareProfile::kDefaults}) {
    const std::string name = presetOf(profile).describe();
    // An empty type hash leaves the user data empty, which is the only intended difference.
    if (!(bareWriterQos(profile) == toWriterQos(presetOf(profile), "", true))) {
      throw std::logic_error("bare DataWriterQos differs from mcvio::dds::toWriterQos for " + name);
    }
    if (!(bareReaderQos(profile) == toReaderQos(presetOf(profile), "", true))) {
      throw std::logic_error("bare DataReaderQos differs from mcvio::dds::toReaderQos for " + name);
    }
  }
}

}  // namespace mcvio::dds::bench
