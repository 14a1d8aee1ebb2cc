#include "bench_transport.hpp"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <stdexcept>

namespace mcvio::dds::bench {

using namespace eprosima::fastdds::dds;

const char* transportName(Transport transport) {
  switch (transport) {
    case Transport::kInProcess:
      return "inproc";
    case Transport::kSharedMemory:
      return "shm";
    case Transport::kUdpLoopback:
      return "udp";
  }
  return "?";
}

Transport parseTransport(const std::string& name) {
  for (Transport t : {Transport::kInProcess, Transport::kSharedMemory, Transport::kUdpLoopback}) {
    if (name == transportName(t)) return t;
  }
  throw std::invalid_argument("unknown transport '" + name + "' (expected inproc, shm or udp)");
}

ParticipantOptions wrapperParticipantOptions(const BusConfig& bus, Transport transport,
                                             const std::string& name) {
  ParticipantOptions options;
  options.domain_id = bus.domain_id;
  options.name = name;
  if (transport == Transport::kUdpLoopback) {
    options.profiles_file = bus.udp_profiles_file;
    options.profile_name = bus.udp_profile_name;
  }
  return options;
}

DomainParticipantQos bareParticipantQos(const BusConfig& bus, Transport transport,
                                        const std::string& name) {
  DomainParticipantQos qos = PARTICIPANT_QOS_DEFAULT;
  if (transport == Transport::kUdpLoopback) {
    auto* factory = DomainParticipantFactory::get_instance();
    if (factory->load_XML_profiles_file(bus.udp_profiles_file) != ReturnCode_t::RETCODE_OK ||
        factory->get_participant_qos_from_profile(bus.udp_profile_name, qos) !=
            ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("participant profile '" + bus.udp_profile_name + "' not found in '" +
                               bus.udp_profiles_file + "'");
    }
  }
  qos.name(name);
  return qos;
}

}  // namespace mcvio::dds::bench
