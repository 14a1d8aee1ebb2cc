#include "mcvio/dds/graph_monitor.hpp"

#include <fastdds/rtps/participant/ParticipantDiscoveryInfo.h>
#include <fastdds/rtps/reader/ReaderDiscoveryInfo.h>
#include <fastdds/rtps/writer/WriterDiscoveryInfo.h>

#include "mcvio/dds/node.hpp"
#include "mcvio/dds/topic_names.hpp"
#include "mcvio/interfaces/type_names.hpp"

namespace mcvio::dds {
namespace {

using namespace eprosima::fastrtps::rtps;
using DiscoveryInfo = rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_;

std::array<std::uint8_t, 16> key(const GUID_t& g) {
  std::array<std::uint8_t, 16> k{};
  std::copy(g.guidPrefix.value, g.guidPrefix.value + 12, k.begin());
  std::copy(g.entityId.value, g.entityId.value + 4, k.begin() + 12);
  return k;
}

std::string typeHashFromUserData(const std::vector<octet>& data) {
  const std::string s(data.begin(), data.end());
  const auto p = s.find("typehash=");
  if (p == std::string::npos) return {};
  const auto e = s.find(';', p);
  return s.substr(p + 9, e == std::string::npos ? std::string::npos : e - p - 9);
}

template <class Qos>
QosProfile profileOf(const Qos& q) {
  QosProfile p;
  p.reliability = q.m_reliability.kind == eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS
                      ? QosProfile::Reliability::kReliable
                      : QosProfile::Reliability::kBestEffort;
  p.durability = q.m_durability.kind == eprosima::fastdds::dds::VOLATILE_DURABILITY_QOS
                     ? QosProfile::Durability::kVolatile
                     : QosProfile::Durability::kTransientLocal;
  return p;
}

DiscoveredTopic describe(const std::string& dds_topic, const std::string& dds_type) {
  DiscoveredTopic t;
  t.dds_topic = dds_topic;
  t.dds_type = dds_type;
  const auto ros_name = toRosTopicName(dds_topic);
  const auto ros_type = interfaces::ddsToRosTypeName(dds_type);
  t.is_ros = ros_name.has_value() && ros_type.has_value();
  t.name = ros_name.value_or(dds_topic);
  t.type = ros_type.value_or(dds_type);
  return t;
}

}  // namespace

GraphMonitor::GraphMonitor() = default;
GraphMonitor::~GraphMonitor() = default;

void GraphMonitor::watchNodes(Node& node) {
  QosProfile qos = QosProfile::transientLocal(100);
  qos.avoid_ros_namespace_conventions = true;
  discovery_subscription_ = node.createSubscription<DiscoveryInfo>("ros_discovery_info", qos, [this](const DiscoveryInfo& info) {
    std::array<std::uint8_t, 12> prefix{};
    std::copy_n(info.gid().data().begin(), 12, prefix.begin());
    std::vector<DiscoveredNode> list;
    for (const auto& n : info.node_entities_info_seq()) list.push_back(DiscoveredNode{n.node_namespace().to_string(), n.node_name().to_string()});
    {
      std::lock_guard<std::mutex> lock(mutex_);
      nodes_[prefix] = std::move(list);
    }
    changed_.notify_all();
  });
}

void GraphMonitor::addEndpoint(const std::array<std::uint8_t, 16>& guid, Endpoint e) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    endpoints_[guid] = std::move(e);
  }
  changed_.notify_all();
}

void GraphMonitor::removeEndpoint(const std::array<std::uint8_t, 16>& guid) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    endpoints_.erase(guid);
  }
  changed_.notify_all();
}

// Writer and reader announcements carry the same fields; one place turns either into an Endpoint.
template <class ProxyData>
GraphMonitor::Endpoint GraphMonitor::endpointOf(const ProxyData& data, bool is_writer) {
  Endpoint e;
  e.dds_topic = data.topicName().to_string();
  e.dds_type = data.typeName().to_string();
  e.type_hash = typeHashFromUserData(data.m_qos.m_userData.data_vec());
  e.is_writer = is_writer;
  e.qos = profileOf(data.m_qos);
  return e;
}

void GraphMonitor::on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant*, WriterDiscoveryInfo&& info) {
  if (info.status == WriterDiscoveryInfo::REMOVED_WRITER) {
    removeEndpoint(key(info.info.guid()));
  } else {
    addEndpoint(key(info.info.guid()), endpointOf(info.info, true));
  }
}

void GraphMonitor::on_subscriber_discovery(eprosima::fastdds::dds::DomainParticipant*, ReaderDiscoveryInfo&& info) {
  if (info.status == ReaderDiscoveryInfo::REMOVED_READER) {
    removeEndpoint(key(info.info.guid()));
  } else {
    addEndpoint(key(info.info.guid()), endpointOf(info.info, false));
  }
}

void GraphMonitor::on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                            ParticipantDiscoveryInfo&& info) {
  if (info.status != ParticipantDiscoveryInfo::REMOVED_PARTICIPANT &&
      info.status != ParticipantDiscoveryInfo::DROPPED_PARTICIPANT) {
    return;
  }
  std::array<std::uint8_t, 12> prefix{};
  std::copy(info.info.m_guid.guidPrefix.value, info.info.m_guid.guidPrefix.value + 12, prefix.begin());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    nodes_.erase(prefix);
    for (auto it = endpoints_.begin(); it != endpoints_.end();) {
      it = std::equal(prefix.begin(), prefix.end(), it->first.begin()) ? endpoints_.erase(it) : std::next(it);
    }
  }
  changed_.notify_all();
}

QosProfile DiscoveredTopic::compatibleReaderQos(bool keep_all_when_reliable) const {
  bool all_reliable = !publisher_qos.empty(), all_transient = !publisher_qos.empty();
  for (const auto& q : publisher_qos) {
    all_reliable = all_reliable && q.reliability == QosProfile::Reliability::kReliable;
    all_transient = all_transient && q.durability == QosProfile::Durability::kTransientLocal;
  }
  QosProfile q = QosProfile::defaults();
  if (all_reliable && keep_all_when_reliable) q = QosProfile::lossless();
  if (!all_reliable) {
    q.reliability = QosProfile::Reliability::kBestEffort;
    q.depth = 100;
  }
  q.durability = all_transient ? QosProfile::Durability::kTransientLocal : QosProfile::Durability::kVolatile;
  return q;
}

std::vector<DiscoveredTopic> GraphMonitor::topics() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<std::string, DiscoveredTopic> by_name;
  for (const auto& [guid, e] : endpoints_) {
    auto it = by_name.find(e.dds_topic);
    if (it == by_name.end()) it = by_name.emplace(e.dds_topic, describe(e.dds_topic, e.dds_type)).first;
    auto& t = it->second;
    if (e.is_writer) {
      ++t.publishers;
      t.publisher_qos.push_back(e.qos);
      if (t.type_hash.empty()) t.type_hash = e.type_hash;
    } else {
      ++t.subscribers;
    }
  }
  std::vector<DiscoveredTopic> out;
  for (auto& [n, t] : by_name) out.push_back(std::move(t));
  return out;
}

std::vector<DiscoveredNode> GraphMonitor::nodes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<DiscoveredNode> out;
  for (const auto& [prefix, list] : nodes_) out.insert(out.end(), list.begin(), list.end());
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.fullName() < b.fullName(); });
  return out;
}

bool GraphMonitor::waitFor(const std::function<bool(const std::vector<DiscoveredTopic>&)>& pred,
                           std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!pred(topics())) {
    std::unique_lock<std::mutex> lock(mutex_);
    const bool timed_out = changed_.wait_until(lock, deadline) == std::cv_status::timeout;
    lock.unlock();
    if (timed_out) return pred(topics());
  }
  return true;
}

}  // namespace mcvio::dds
