#include "mcvio/dds/fastdds_qos.hpp"

namespace mcvio::dds {
namespace {

using namespace eprosima::fastdds::dds;

std::vector<eprosima::fastrtps::rtps::octet> typeHashUserData(const std::string& type_hash) {
  if (type_hash.empty()) return {};
  const std::string s = "typehash=" + type_hash + ";";
  return {s.begin(), s.end()};
}

template <class Qos>
void applyCommon(Qos& qos, const QosProfile& p, bool unbounded_type) {
  qos.reliability().kind = p.reliability == QosProfile::Reliability::kReliable ? RELIABLE_RELIABILITY_QOS
                                                                              : BEST_EFFORT_RELIABILITY_QOS;
  qos.durability().kind = p.durability == QosProfile::Durability::kTransientLocal ? TRANSIENT_LOCAL_DURABILITY_QOS
                                                                                  : VOLATILE_DURABILITY_QOS;
  qos.history().kind = p.history == QosProfile::History::kKeepAll ? KEEP_ALL_HISTORY_QOS : KEEP_LAST_HISTORY_QOS;
  qos.history().depth = p.history == QosProfile::History::kKeepAll ? 1 : p.depth;
  if (p.history == QosProfile::History::kKeepAll) {
    // Bounded memory even when keeping all: a full history blocks the writer (flow control)
    // rather than growing without limit.
    qos.resource_limits().max_samples = 100;
    qos.resource_limits().max_instances = 1;
    qos.resource_limits().max_samples_per_instance = 100;
  }
  // Images and sequences have no fixed size: let the payload pool grow instead of preallocating
  // the worst case.
  if (unbounded_type) {
    qos.endpoint().history_memory_policy = eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  }
}

}  // namespace

DataWriterQos toWriterQos(const QosProfile& profile, const std::string& type_hash, bool unbounded_type) {
  DataWriterQos qos = DATAWRITER_QOS_DEFAULT;
  applyCommon(qos, profile, unbounded_type);
  if (profile.history == QosProfile::History::kKeepAll) {
    qos.reliability().max_blocking_time = eprosima::fastrtps::Duration_t(1, 0);
  }
  // Late joiners of transient-local topics (calibration, ros_discovery_info) get the history at
  // the next heartbeat: Fast DDS's 3 s default makes `mcvio nodes` miss them.
  qos.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(0, 100000000);
  qos.user_data().data_vec(typeHashUserData(type_hash));
  return qos;
}

DataReaderQos toReaderQos(const QosProfile& profile, const std::string& type_hash, bool unbounded_type) {
  DataReaderQos qos = DATAREADER_QOS_DEFAULT;
  applyCommon(qos, profile, unbounded_type);
  if (profile.history == QosProfile::History::kKeepAll) {
    // A keep-all writer's window waits for our ACKNACK; Fast DDS's 5 ms default response delay
    // caps lossless small-message streams at ~14k msgs/s (measured: 1 ms doubles that).
    qos.reliable_reader_qos().times.heartbeatResponseDelay = eprosima::fastrtps::Duration_t(0, 1000000);
  }
  qos.user_data().data_vec(typeHashUserData(type_hash));
  return qos;
}

}  // namespace mcvio::dds
