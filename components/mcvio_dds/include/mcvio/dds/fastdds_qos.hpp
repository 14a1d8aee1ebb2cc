#pragma once
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

#include "mcvio/dds/qos_profile.hpp"

namespace mcvio::dds {

/// Fast DDS writer QoS for a profile, with the writer's `typehash=…;` user data as rmw does.
eprosima::fastdds::dds::DataWriterQos toWriterQos(const QosProfile& profile, const std::string& type_hash,
                                                  bool unbounded_type);
/// Fast DDS reader QoS for a profile.
eprosima::fastdds::dds::DataReaderQos toReaderQos(const QosProfile& profile, const std::string& type_hash,
                                                  bool unbounded_type);

}  // namespace mcvio::dds
