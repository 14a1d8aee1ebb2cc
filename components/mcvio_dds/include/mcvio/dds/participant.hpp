#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "mcvio/core/topic_remapping.hpp"

namespace mcvio::dds {

/// How to join the DDS bus. Defaults follow ROS 2: domain from ROS_DOMAIN_ID, enclave "/".
struct ParticipantOptions {
  int domain_id = 0;           ///< 0..232 (the UDP port mapping of RTPS runs out above 232)
  std::string profiles_file;   ///< Fast DDS XML profiles (config/dds/*.xml); empty = defaults
  std::string profile_name;    ///< participant profile in that file; empty = its default profile
  std::string name = "mcvio";  ///< participant name shown by DDS tools
  std::string enclave = "/";   ///< ROS 2 security enclave announced in user data

  /// Defaults with domain_id from ROS_DOMAIN_ID and profiles_file from MCVIO_DDS_PROFILES when set.
  static ParticipantOptions fromEnvironment();
  /// Throws std::invalid_argument naming the bad field (domain id range, missing profiles file).
  void validate() const;
};

class Node;

/// One DDS domain participant that ROS 2 sees as a process with one or more nodes.
///
/// It owns the DDS publisher/subscriber, registers types and topics once, announces
/// `enclave=/;` in its user data and publishes `ros_discovery_info`
/// (rmw_dds_common/msg/ParticipantEntitiesInfo, Jazzy layout) listing every node's readers and
/// writers, which is what makes `ros2 node list` and rqt_graph show mcvio's components.
class Participant : public std::enable_shared_from_this<Participant> {
 public:
  /// Creates the participant. Throws mcvio::InputError for an XML profile that does not load and
  /// std::invalid_argument for bad options.
  /// `listener` (optional, outliving the participant) sees discovery from the first moment.
  static std::shared_ptr<Participant> create(const ParticipantOptions& options,
                                             eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  /// Adds a ROS 2 node ("frontend", namespace "/") hosted by this participant.
  std::shared_ptr<Node> createNode(const std::string& name, const std::string& ns = "/", TopicRemapping remapping = {});

  const ParticipantOptions& options() const { return options_; }
  eprosima::fastdds::dds::DomainParticipant* native() const { return participant_; }
  /// The 16-byte GID (GUID prefix + entity id) ROS 2 uses to name this participant.
  std::vector<std::uint8_t> gid() const;

  // ---- used by Node, Publisher and Subscription -------------------------------------------
  /// Registers a type once; a second registration of the same name with a different support
  /// (e.g. typed and generic in one participant) throws std::logic_error.
  void registerType(eprosima::fastdds::dds::TypeSupport type);
  /// Finds or creates the DDS topic; counted, released with releaseTopic().
  eprosima::fastdds::dds::Topic* acquireTopic(const std::string& dds_topic, const std::string& dds_type);
  void releaseTopic(eprosima::fastdds::dds::Topic* topic);
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }
  /// Node bookkeeping for ros_discovery_info.
  void addEndpoint(const std::string& node_key, const std::vector<std::uint8_t>& gid, bool is_writer);
  void removeEndpoint(const std::string& node_key, const std::vector<std::uint8_t>& gid);
  void removeNode(const std::string& node_key);

 private:
  Participant(ParticipantOptions options, eprosima::fastdds::dds::DomainParticipantListener* listener);
  void publishDiscoveryInfo();

  struct NodeEntry {
    std::string name, ns;
    std::vector<std::vector<std::uint8_t>> readers, writers;
  };
  ParticipantOptions options_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::Topic* discovery_topic_ = nullptr;
  eprosima::fastdds::dds::DataWriter* discovery_writer_ = nullptr;
  std::mutex mutex_;
  std::map<std::string, std::pair<eprosima::fastdds::dds::Topic*, int>> topics_;
  std::map<std::string, NodeEntry> nodes_;
};

/// The 16-byte ROS 2 GID of a DDS entity.
std::vector<std::uint8_t> gidOf(const eprosima::fastrtps::rtps::GUID_t& guid);

}  // namespace mcvio::dds
