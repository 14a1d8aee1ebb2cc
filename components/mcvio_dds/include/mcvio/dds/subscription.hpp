#pragma once
#include <functional>
#include <string>

#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "mcvio/dds/endpoint.hpp"
#include "mcvio/interfaces/message_registry.hpp"
#include "mcvio/interfaces/ros_type_traits.hpp"

namespace mcvio::dds {

/// Receives one generated ROS 2 type from one topic and hands each sample to a callback
/// (rclcpp::Subscription's role). The callback runs on a Fast DDS thread.
template <class T>
class Subscription : public ReaderEndpoint, private eprosima::fastdds::dds::DataReaderListener {
 public:
  Subscription(Node& node, const std::string& topic, const QosProfile& qos, std::function<void(const T&)> callback)
      : ReaderEndpoint(node, topic,
                       eprosima::fastdds::dds::TypeSupport(new typename interfaces::RosType<T>::PubSubType()),
                       std::string(interfaces::MessageRegistry::get(interfaces::RosType<T>::kName).type_hash),
                       qos),
        callback_(std::move(callback)) {
    start(this);
  }
  ~Subscription() override { shutdown(); }

 private:
  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    eprosima::fastdds::dds::SampleInfo info;
    SubscriptionCallbackScope scope;
    while (reader->take_next_sample(&sample_, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) callback_(sample_);
    }
  }

  std::function<void(const T&)> callback_;
  T sample_;
};

}  // namespace mcvio::dds
