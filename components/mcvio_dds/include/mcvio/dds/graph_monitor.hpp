#pragma once
#include <array>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <fastdds/dds/domain/DomainParticipantListener.hpp>

#include "mcvio/dds/endpoint.hpp"
#include "mcvio/dds/qos_profile.hpp"

namespace mcvio::dds {

class Node;
template <class T> class Subscription;

/// A topic seen on the bus, as `ros2 topic list -t` shows it.
struct DiscoveredTopic {
  std::string name;       ///< ROS 2 name ("/cam0/image_raw"), or the DDS name for non-ROS topics
  std::string type;       ///< ROS 2 type ("sensor_msgs/msg/Image"), or the DDS type name
  std::string dds_topic;  ///< "rt/cam0/image_raw"
  std::string dds_type;   ///< "sensor_msgs::msg::dds_::Image_"
  std::string type_hash;  ///< from a writer's user data, when it announced one
  int publishers = 0;
  int subscribers = 0;
  std::vector<QosProfile> publisher_qos;  ///< reliability and durability as offered (history unknown)
  bool is_ros = false;

  /// A reader every offered writer matches: reliable (keep-all when `keep_all_when_reliable`) and
  /// transient local only when all writers offer them; best effort, depth 100, otherwise.
  QosProfile compatibleReaderQos(bool keep_all_when_reliable = false) const;
};

/// A ROS 2 node announced in some participant's ros_discovery_info.
struct DiscoveredNode {
  std::string ns, name;
  std::string fullName() const { return ns == "/" ? "/" + name : ns + "/" + name; }
};

/// Watches discovery: every remote (and local) writer and reader, and every participant's
/// ros_discovery_info, so commands can list topics and nodes and the recorder can subscribe to
/// topics as they appear (it polls topics(): entities must not be created on discovery threads).
/// Pass it to Participant::create() so it sees discovery from the start.
class GraphMonitor : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  GraphMonitor();
  ~GraphMonitor() override;

  /// Subscribes to ros_discovery_info through `node` so nodes() can name the nodes.
  void watchNodes(Node& node);

  std::vector<DiscoveredTopic> topics() const;
  std::vector<DiscoveredNode> nodes() const;
  /// Waits until `pred(topics())` holds or the timeout passes.
  bool waitFor(const std::function<bool(const std::vector<DiscoveredTopic>&)>& pred, std::chrono::milliseconds timeout);

  void on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override;
  void on_subscriber_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                               eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override;
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;

 private:
  struct Endpoint {
    std::string dds_topic, dds_type, type_hash;
    bool is_writer = false;
    QosProfile qos;
  };
  template <class ProxyData>
  static Endpoint endpointOf(const ProxyData& data, bool is_writer);
  void addEndpoint(const std::array<std::uint8_t, 16>& guid, Endpoint e);
  void removeEndpoint(const std::array<std::uint8_t, 16>& guid);

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::array<std::uint8_t, 16>, Endpoint> endpoints_;
  std::map<std::array<std::uint8_t, 12>, std::vector<DiscoveredNode>> nodes_;  // by participant prefix
  std::unique_ptr<ReaderEndpoint> discovery_subscription_;
};

}  // namespace mcvio::dds
