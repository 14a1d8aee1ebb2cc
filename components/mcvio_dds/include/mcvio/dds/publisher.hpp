#pragma once
#include <string>

#include "mcvio/dds/endpoint.hpp"
#include "mcvio/interfaces/message_registry.hpp"
#include "mcvio/interfaces/ros_type_traits.hpp"

namespace mcvio::dds {

/// Publishes one generated ROS 2 type on one topic (rclcpp::Publisher's role).
template <class T>
class Publisher : public WriterEndpoint {
 public:
  Publisher(Node& node, const std::string& topic, const QosProfile& qos)
      : WriterEndpoint(node, topic,
                       eprosima::fastdds::dds::TypeSupport(new typename interfaces::RosType<T>::PubSubType()),
                       std::string(interfaces::MessageRegistry::get(interfaces::RosType<T>::kName).type_hash),
                       qos) {}

  /// Sends `msg`; false only when a lossless reader blocked us past the give-up time.
  bool publish(const T& msg) { return write(const_cast<T*>(&msg)); }
};

}  // namespace mcvio::dds
