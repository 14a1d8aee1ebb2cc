#pragma once
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

namespace mcvio::dds::bench {

// Written out by hand, as a bare Fast DDS user would, for the two mcvio::dds presets the benchmark
// uses, on an unbounded type (Image and Imu hold strings and sequences).
// checkBareQosMatchesWrapper() proves at start-up that they equal
// mcvio::dds::toWriterQos/toReaderQos apart from the type-hash user data, so wrapper and bare
// endpoints are compared under identical QoS.

/// The mcvio::dds preset a bare endpoint mirrors.
enum class BareProfile {
  kLossless,  ///< QosProfile::lossless(): reliable, volatile, keep all <= 100 samples, 1 s max
              ///< blocking
  kDefaults,  ///< QosProfile::defaults(): reliable, volatile, keep last 10
};

/// Writer QoS for `profile`, with the reallocating payload pool mcvio uses for unbounded types.
eprosima::fastdds::dds::DataWriterQos bareWriterQos(BareProfile profile);
/// Reader QoS for `profile`, with the reallocating payload pool mcvio uses for unbounded types.
eprosima::fastdds::dds::DataReaderQos bareReaderQos(BareProfile profile);
/// Throws std::logic_error when the hand-written QoS drifted away from mcvio::dds's presets.
void checkBareQosMatchesWrapper();

}  // namespace mcvio::dds::bench
