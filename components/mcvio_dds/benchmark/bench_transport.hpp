#pragma once
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <string>

#include "mcvio/dds/participant.hpp"

namespace mcvio::dds::bench {

/// Where the ping and the pong travel.
enum class Transport {
  kInProcess,     ///< both ends in one participant: Fast DDS intraprocess delivery
  kSharedMemory,  ///< an echo child process, Fast DDS default transports (SHM between processes on
                  ///< one host)
  kUdpLoopback,   ///< an echo child process, UDPv4 on 127.0.0.1 only, no SHM
                  ///< (config/dds/localhost_udp.xml)
};

/// "inproc", "shm", "udp": command-line spelling for the echo child and benchmark names.
const char* transportName(Transport transport);
/// Inverse of transportName; throws std::invalid_argument for anything else.
Transport parseTransport(const std::string& name);

/// What both the measuring process and its echo child need to join the same bus.
struct BusConfig {
  int domain_id = 0;
  /// Fast DDS XML with the participant profile `udp_profile_name` (UDP on loopback, no SHM).
  std::string udp_profiles_file;
  std::string udp_profile_name = "localhost_udp";
  /// false: bare endpoints live in the wrapper's participant (same threads, an A/B of the code
  /// path only); true: in a DomainParticipant of their own with the same participant QoS.
  bool bare_in_own_participant = false;
};

/// Options for an mcvio::dds::Participant on `transport`.
ParticipantOptions wrapperParticipantOptions(const BusConfig& bus, Transport transport,
                                             const std::string& name);
/// The same participant settings for a bare DomainParticipant: Fast DDS defaults, or the UDP
/// profile read from the same XML file the wrapper loads. Throws std::runtime_error when the
/// profile is missing.
eprosima::fastdds::dds::DomainParticipantQos bareParticipantQos(const BusConfig& bus,
                                                                Transport transport,
                                                                const std::string& name);

}  // namespace mcvio::dds::bench
