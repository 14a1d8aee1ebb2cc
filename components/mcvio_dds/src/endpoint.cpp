#include "mcvio/dds/endpoint.hpp"

#include <cstdio>
#include <thread>

#include <fastdds/dds/core/status/PublicationMatchedStatus.hpp>
#include <fastdds/dds/core/status/SubscriptionMatchedStatus.hpp>

#include "mcvio/dds/fastdds_qos.hpp"
#include "mcvio/dds/node.hpp"
#include "mcvio/dds/topic_names.hpp"

namespace mcvio::dds {

using namespace eprosima::fastdds::dds;

namespace {

std::string ddsTopicFor(const std::string& topic, const QosProfile& qos) {
  if (qos.avoid_ros_namespace_conventions) {
    if (topic.empty()) throw std::invalid_argument("empty DDS topic name");
    return topic;
  }
  return toDdsTopicName(topic);
}

std::string displayName(const std::string& topic, const QosProfile& qos) {
  if (qos.avoid_ros_namespace_conventions || topic.empty() || topic.front() == '/') return topic;
  return "/" + topic;
}

// The node's remap rules apply to ROS topics, not to plain DDS ones (ros_discovery_info).
std::string remapped(const Node& node, const std::string& topic, const QosProfile& qos) {
  if (qos.avoid_ros_namespace_conventions || topic.empty()) return topic;
  return node.resolveTopic(topic);
}

}  // namespace

WriterEndpoint::WriterEndpoint(Node& node, const std::string& ros_topic, TypeSupport type,
                               const std::string& type_hash, const QosProfile& qos)
      : node_(node.shared_from_this()), ros_topic_(displayName(remapped(node, ros_topic, qos), qos)), qos_(qos) {
  const std::string dds_topic = ddsTopicFor(ros_topic_, qos);
  const bool unbounded = !type->is_bounded();
  const std::string type_name = type.get_type_name();
  node_->participant()->registerType(type);
  topic_ = node_->participant()->acquireTopic(dds_topic, type_name);
  writer_ = node_->participant()->publisher()->create_datawriter(topic_, toWriterQos(qos, type_hash, unbounded));
  if (!writer_) {
    node_->participant()->releaseTopic(topic_);
    throw std::runtime_error("Fast DDS could not create a writer for " + ros_topic_);
  }
  node_->participant()->addEndpoint(node_->key(), gidOf(writer_->guid()), true);
}

WriterEndpoint::~WriterEndpoint() {
  node_->participant()->removeEndpoint(node_->key(), gidOf(writer_->guid()));
  node_->participant()->publisher()->delete_datawriter(writer_);
  node_->participant()->releaseTopic(topic_);
}

int WriterEndpoint::matchedReaders() const {
  PublicationMatchedStatus status;
  writer_->get_publication_matched_status(status);
  return status.current_count;
}

bool WriterEndpoint::waitForReaders(int count, std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (matchedReaders() < count) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

bool WriterEndpoint::waitForAcknowledgments(std::chrono::milliseconds timeout) const {
  const auto ms = timeout.count();
  return writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(
             static_cast<int32_t>(ms / 1000), static_cast<uint32_t>((ms % 1000) * 1000000))) ==
         ReturnCode_t::RETCODE_OK;
}

bool& inSubscriptionCallback() {
  thread_local bool in_callback = false;
  return in_callback;
}

bool WriterEndpoint::write(void* sample, std::chrono::milliseconds give_up) {
  if (writer_->write(sample)) return true;
  if (qos_.history != QosProfile::History::kKeepAll) return false;
  if (inSubscriptionCallback()) {
    std::fprintf(stderr, "mcvio: %s: lossless write from a subscription callback found the reader full; "
                 "sample dropped (publish lossless streams from the component's own thread)\n", ros_topic_.c_str());
    return false;
  }
  // A keep-all writer whose readers are behind returns false after max_blocking_time: try again
  // so a slow reader slows us down instead of losing samples.
  const auto deadline = std::chrono::steady_clock::now() + give_up;
  while (!writer_->write(sample)) {
    if (std::chrono::steady_clock::now() > deadline) return false;
  }
  return true;
}

ReaderEndpoint::ReaderEndpoint(Node& node, const std::string& ros_topic, TypeSupport type,
                               const std::string& type_hash, const QosProfile& qos)
      : node_(node.shared_from_this()), ros_topic_(displayName(remapped(node, ros_topic, qos), qos)) {
  const std::string dds_topic = ddsTopicFor(ros_topic_, qos);
  const bool unbounded = !type->is_bounded();
  const std::string type_name = type.get_type_name();
  node_->participant()->registerType(type);
  topic_ = node_->participant()->acquireTopic(dds_topic, type_name);
  reader_qos_ = toReaderQos(qos, type_hash, unbounded);
}

void ReaderEndpoint::start(DataReaderListener* listener) {
  reader_ = node_->participant()->subscriber()->create_datareader(topic_, reader_qos_, listener);
  if (!reader_) {
    node_->participant()->releaseTopic(topic_);
    topic_ = nullptr;
    throw std::runtime_error("Fast DDS could not create a reader for " + ros_topic_);
  }
  node_->participant()->addEndpoint(node_->key(), gidOf(reader_->guid()), false);
}

void ReaderEndpoint::shutdown() {
  if (!reader_) return;
  reader_->set_listener(nullptr);
  node_->participant()->removeEndpoint(node_->key(), gidOf(reader_->guid()));
  node_->participant()->subscriber()->delete_datareader(reader_);
  reader_ = nullptr;
}

ReaderEndpoint::~ReaderEndpoint() {
  shutdown();
  if (topic_) node_->participant()->releaseTopic(topic_);
}

int ReaderEndpoint::matchedWriters() const {
  SubscriptionMatchedStatus status;
  reader_->get_subscription_matched_status(status);
  return status.current_count;
}

}  // namespace mcvio::dds
