#include "mcvio/dds/generic_subscription.hpp"

#include <chrono>

#include <fastdds/dds/subscriber/SampleInfo.hpp>

namespace mcvio::dds {

GenericSubscription::GenericSubscription(Node& node, const std::string& ros_topic, const std::string& dds_type,
                                         const std::string& type_hash, const QosProfile& qos,
                                         std::function<void(const ReceivedPayload&)> callback)
    : ReaderEndpoint(node, ros_topic, eprosima::fastdds::dds::TypeSupport(new RawPayloadType(dds_type)), type_hash,
                     qos),
      callback_(std::move(callback)) {
  start(this);
}

GenericSubscription::~GenericSubscription() { shutdown(); }

void GenericSubscription::on_data_available(eprosima::fastdds::dds::DataReader* reader) {
  eprosima::fastdds::dds::SampleInfo info;
  SubscriptionCallbackScope scope;
  while (reader->take_next_sample(&sample_, &info) == ReturnCode_t::RETCODE_OK) {
    if (!info.valid_data) continue;
    ReceivedPayload p;
    p.payload = &sample_;
    p.receive_time_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::system_clock::now().time_since_epoch())
                            .count();
    p.source_time_ns = info.source_timestamp.to_ns();
    callback_(p);
  }
}

GenericPublisher::GenericPublisher(Node& node, const std::string& ros_topic, const std::string& dds_type,
                                   const std::string& type_hash, const QosProfile& qos)
    : WriterEndpoint(node, ros_topic, eprosima::fastdds::dds::TypeSupport(new RawPayloadType(dds_type)), type_hash,
                     qos) {}

}  // namespace mcvio::dds
