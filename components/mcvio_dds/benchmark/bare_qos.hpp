#pragma once
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <string>

#include "mcvio/dds/fastdds_qos.hpp"
#include "mcvio/dds/qos_profile.hpp"
#include "mcvio/interfaces/message_registry.hpp"
#include "mcvio/interfaces/ros_type_traits.hpp"

namespace mcvio::dds::bench {

// The bare endpoints take the very QoS objects mcvio::dds builds for its own endpoints of type T
// (type-hash user data included), so the comparison measures the per-message code path and stays
// fair whenever the presets are tuned. QoS is built once per endpoint: it is not part of the cost
// being measured.

template <class T>
std::string typeHashOf() {
  return std::string(interfaces::MessageRegistry::get(interfaces::RosType<T>::kName).type_hash);
}

/// DataWriterQos of an mcvio::dds publisher of T with `profile`.
template <class T>
eprosima::fastdds::dds::DataWriterQos bareWriterQos(const QosProfile& profile) {
  typename interfaces::RosType<T>::PubSubType type;
  return toWriterQos(profile, typeHashOf<T>(), !type.is_bounded());
}

/// DataReaderQos of an mcvio::dds subscription of T with `profile`.
template <class T>
eprosima::fastdds::dds::DataReaderQos bareReaderQos(const QosProfile& profile) {
  typename interfaces::RosType<T>::PubSubType type;
  return toReaderQos(profile, typeHashOf<T>(), !type.is_bounded());
}

}  // namespace mcvio::dds::bench
