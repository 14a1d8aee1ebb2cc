#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include <fastdds/dds/subscriber/DataReaderListener.hpp>

#include "mcvio/dds/endpoint.hpp"
#include "mcvio/dds/raw_payload_type.hpp"

namespace mcvio::dds {

/// One sample as the recorder stores it.
struct ReceivedPayload {
  const RawPayload* payload = nullptr;  ///< serialized CDR incl. encapsulation header
  std::int64_t receive_time_ns = 0;     ///< when we took it (system clock)
  std::int64_t source_time_ns = 0;      ///< the writer's source timestamp
};

/// Receives any topic's serialized payload without knowing the type at compile time.
/// `dds_type` is the discovered DDS type name (e.g. "sensor_msgs::msg::dds_::Image_").
/// The participant must not also hold a typed registration of that type.
class GenericSubscription : public ReaderEndpoint, private eprosima::fastdds::dds::DataReaderListener {
 public:
  GenericSubscription(Node& node, const std::string& ros_topic, const std::string& dds_type,
                      const std::string& type_hash, const QosProfile& qos,
                      std::function<void(const ReceivedPayload&)> callback);
  ~GenericSubscription() override;

 private:
  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;
  std::function<void(const ReceivedPayload&)> callback_;
  RawPayload sample_;
};

/// Publishes serialized payloads under any type name (bag playback of types we have no code for).
class GenericPublisher : public WriterEndpoint {
 public:
  GenericPublisher(Node& node, const std::string& ros_topic, const std::string& dds_type,
                   const std::string& type_hash, const QosProfile& qos);
  bool publish(const RawPayload& payload) { return write(const_cast<RawPayload*>(&payload)); }
};

}  // namespace mcvio::dds
