#include "mcvio/dds/participant.hpp"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dds/node.hpp"
#include "mcvio/interfaces/message_registry.hpp"
#include "mcvio/interfaces/ros_type_traits.hpp"

namespace mcvio::dds {
namespace {

using namespace eprosima::fastdds::dds;
using DiscoveryInfo = rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_;

constexpr int kMaxDomainId = 232;

std::array<std::uint8_t, 16> toGidArray(const std::vector<std::uint8_t>& gid) {
  std::array<std::uint8_t, 16> a{};
  std::copy_n(gid.begin(), std::min<std::size_t>(16, gid.size()), a.begin());
  return a;
}

}  // namespace

std::vector<std::uint8_t> gidOf(const eprosima::fastrtps::rtps::GUID_t& guid) {
  std::vector<std::uint8_t> g(guid.guidPrefix.value, guid.guidPrefix.value + 12);
  g.insert(g.end(), guid.entityId.value, guid.entityId.value + 4);
  return g;
}

ParticipantOptions ParticipantOptions::fromEnvironment() {
  ParticipantOptions o;
  if (const char* d = std::getenv("ROS_DOMAIN_ID"); d && *d) {
    char* end = nullptr;
    const long v = std::strtol(d, &end, 10);
    if (*end != '\0') throw std::invalid_argument(std::string("ROS_DOMAIN_ID='") + d + "' is not a number");
    o.domain_id = static_cast<int>(v);
  }
  if (const char* p = std::getenv("MCVIO_DDS_PROFILES"); p && *p) o.profiles_file = p;
  return o;
}

void ParticipantOptions::validate() const {
  if (domain_id < 0 || domain_id > kMaxDomainId) {
    throw std::invalid_argument("domain id " + std::to_string(domain_id) + " is out of range 0.." +
                                std::to_string(kMaxDomainId));
  }
  if (!profiles_file.empty() && !std::filesystem::is_regular_file(profiles_file)) {
    throw std::invalid_argument("DDS profiles file '" + profiles_file + "' does not exist");
  }
}

std::shared_ptr<Participant> Participant::create(const ParticipantOptions& options,
                                                 DomainParticipantListener* listener) {
  options.validate();
  return std::shared_ptr<Participant>(new Participant(options, listener));
}

Participant::Participant(ParticipantOptions options, DomainParticipantListener* listener)
    : options_(std::move(options)) {
  auto* factory = DomainParticipantFactory::get_instance();
  DomainParticipantQos qos = PARTICIPANT_QOS_DEFAULT;
  if (!options_.profiles_file.empty()) {
    if (factory->load_XML_profiles_file(options_.profiles_file) != ReturnCode_t::RETCODE_OK) {
      throw InputError("DDS profiles file '" + options_.profiles_file +
                       "' could not be loaded: malformed XML or an element Fast DDS does not know");
    }
    if (!options_.profile_name.empty()) {
      if (factory->get_participant_qos_from_profile(options_.profile_name, qos) != ReturnCode_t::RETCODE_OK) {
        throw InputError("DDS profiles file '" + options_.profiles_file + "' has no participant profile '" +
                         options_.profile_name + "'");
      }
    } else {
      factory->get_default_participant_qos(qos);
    }
  } else if (!options_.profile_name.empty()) {
    throw std::invalid_argument("profile '" + options_.profile_name + "' given without a profiles file");
  } else {
    // Fast DDS's built-in transports, sized for camera streams: its 512 kB shared-memory segment
    // holds one 752x480 image, so a stereo pair in flight drops samples (measured: 3 of 95
    // images lost recording at 1x), and ~200 kB UDP buffers force a repair per image.
    using namespace eprosima::fastdds::rtps;
    qos.transport().use_builtin_transports = false;
    auto shm = std::make_shared<SharedMemTransportDescriptor>();
    shm->segment_size(8 * 1024 * 1024);
    qos.transport().user_transports.push_back(shm);
    auto udp = std::make_shared<UDPv4TransportDescriptor>();
    udp->sendBufferSize = 4 * 1024 * 1024;
    udp->receiveBufferSize = 4 * 1024 * 1024;
    qos.transport().user_transports.push_back(udp);
  }
  qos.name(options_.name);
  const std::string enclave = "enclave=" + options_.enclave + ";";
  qos.user_data().data_vec(std::vector<eprosima::fastrtps::rtps::octet>(enclave.begin(), enclave.end()));
  // Discovery callbacks are not gated by the mask; an empty mask keeps the participant listener
  // from taking data-available events that belong to each reader's own listener.
  participant_ = factory->create_participant(static_cast<DomainId_t>(options_.domain_id), qos, listener,
                                             StatusMask::none());
  if (!participant_) {
    throw std::runtime_error("Fast DDS could not create a participant on domain " +
                             std::to_string(options_.domain_id) + " (see its log above)");
  }
  publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);

  // ros_discovery_info: reliable, transient local, keep last 1, as rmw_dds_common's graph cache.
  using Traits = interfaces::RosType<DiscoveryInfo>;
  registerType(TypeSupport(new Traits::PubSubType()));
  discovery_topic_ = acquireTopic("ros_discovery_info", "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_");
  DataWriterQos wqos = DATAWRITER_QOS_DEFAULT;
  wqos.reliability().kind = RELIABLE_RELIABILITY_QOS;
  wqos.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
  wqos.history().kind = KEEP_LAST_HISTORY_QOS;
  wqos.history().depth = 1;
  wqos.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(0, 100000000);
  const std::string th = "typehash=" + std::string(interfaces::MessageRegistry::get(Traits::kName).type_hash) + ";";
  wqos.user_data().data_vec(std::vector<eprosima::fastrtps::rtps::octet>(th.begin(), th.end()));
  discovery_writer_ = publisher_->create_datawriter(discovery_topic_, wqos);
  publishDiscoveryInfo();
}

Participant::~Participant() {
  if (!participant_) return;
  participant_->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

std::vector<std::uint8_t> Participant::gid() const { return gidOf(participant_->guid()); }

std::shared_ptr<Node> Participant::createNode(const std::string& name, const std::string& ns, TopicRemapping remapping) {
  return std::make_shared<Node>(shared_from_this(), name, ns, std::move(remapping));
}

void Participant::registerType(TypeSupport type) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string name = type.get_type_name();
  TypeSupport existing = participant_->find_type(name);
  if (!existing.empty()) {
    if (typeid(*existing.get()) != typeid(*type.get())) {
      throw std::logic_error("type " + name + " is already registered in this participant with another "
                             "representation (typed vs generic); use a separate participant");
    }
    return;
  }
  if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK) {
    throw std::runtime_error("Fast DDS refused to register type " + name);
  }
}

Topic* Participant::acquireTopic(const std::string& dds_topic, const std::string& dds_type) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = topics_.find(dds_topic);
  if (it != topics_.end()) {
    if (it->second.first->get_type_name() != dds_type) {
      throw std::invalid_argument("topic '" + dds_topic + "' is already used with type " +
                                  it->second.first->get_type_name() + ", not " + dds_type);
    }
    ++it->second.second;
    return it->second.first;
  }
  Topic* t = participant_->create_topic(dds_topic, dds_type, TOPIC_QOS_DEFAULT);
  if (!t) throw std::runtime_error("Fast DDS could not create topic '" + dds_topic + "' of type " + dds_type);
  topics_[dds_topic] = {t, 1};
  return t;
}

void Participant::releaseTopic(Topic* topic) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = topics_.begin(); it != topics_.end(); ++it) {
    if (it->second.first == topic && --it->second.second == 0) {
      participant_->delete_topic(topic);
      topics_.erase(it);
      return;
    }
  }
}

void Participant::addEndpoint(const std::string& node_key, const std::vector<std::uint8_t>& gid, bool is_writer) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto& node = nodes_[node_key];
    if (node.name.empty()) {
      const auto slash = node_key.rfind('/');
      node.ns = slash == 0 ? "/" : node_key.substr(0, slash);
      node.name = node_key.substr(slash + 1);
    }
    if (!gid.empty()) (is_writer ? node.writers : node.readers).push_back(gid);
  }
  publishDiscoveryInfo();
}

void Participant::removeEndpoint(const std::string& node_key, const std::vector<std::uint8_t>& gid) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = nodes_.find(node_key);
    if (it == nodes_.end()) return;
    for (auto* v : {&it->second.readers, &it->second.writers}) {
      v->erase(std::remove(v->begin(), v->end(), gid), v->end());
    }
  }
  publishDiscoveryInfo();
}

void Participant::removeNode(const std::string& node_key) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    nodes_.erase(node_key);
  }
  publishDiscoveryInfo();
}

void Participant::publishDiscoveryInfo() {
  DiscoveryInfo info;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    info.gid().data(toGidArray(gid()));
    for (const auto& [key, node] : nodes_) {
      rmw_dds_common::msg::dds_::NodeEntitiesInfo_ n;
      n.node_namespace(node.ns);
      n.node_name(node.name);
      for (const auto& g : node.readers) {
        rmw_dds_common::msg::dds_::Gid_ gid;
        gid.data(toGidArray(g));
        n.reader_gid_seq().push_back(gid);
      }
      for (const auto& g : node.writers) {
        rmw_dds_common::msg::dds_::Gid_ gid;
        gid.data(toGidArray(g));
        n.writer_gid_seq().push_back(gid);
      }
      info.node_entities_info_seq().push_back(n);
    }
  }
  if (discovery_writer_) discovery_writer_->write(&info);
}

}  // namespace mcvio::dds
