#include "bare_participant.hpp"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <stdexcept>

namespace mcvio::dds::bench {

using namespace eprosima::fastdds::dds;

BareParticipant::BareParticipant(int domain_id, const DomainParticipantQos& qos) {
  participant_ = DomainParticipantFactory::get_instance()->create_participant(
      static_cast<DomainId_t>(domain_id), qos);
  if (!participant_)
    throw std::runtime_error("Fast DDS could not create a bare participant on domain " +
                             std::to_string(domain_id));
  publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  if (!publisher_ || !subscriber_) {
    DomainParticipantFactory::get_instance()->delete_participant(participant_);
    throw std::runtime_error(
        "Fast DDS could not create a publisher/subscriber on the bare participant");
  }
}

BareParticipant::BareParticipant(const Participant& host)
    : participant_(host.native()),
      publisher_(host.publisher()),
      subscriber_(host.subscriber()),
      owns_participant_(false) {}

BareParticipant::~BareParticipant() {
  if (owns_participant_) {
    participant_->delete_contained_entities();
    DomainParticipantFactory::get_instance()->delete_participant(participant_);
    return;
  }
  for (auto& [name, topic] : topics_) participant_->delete_topic(topic);
}

std::unique_ptr<BareParticipant> makeBareParticipant(const BusConfig& bus, Transport transport,
                                                     const Participant& host,
                                                     const std::string& name) {
  if (!bus.bare_in_own_participant) return std::make_unique<BareParticipant>(host);
  return std::make_unique<BareParticipant>(bus.domain_id, bareParticipantQos(bus, transport, name));
}

Topic* BareParticipant::topic(const std::string& name, TypeSupport type) {
  auto it = topics_.find(name);
  if (it != topics_.end()) return it->second;
  const std::string type_name = type.get_type_name();
  if (participant_->find_type(type_name).empty() &&
      type.register_type(participant_) != ReturnCode_t::RETCODE_OK) {
    throw std::runtime_error("Fast DDS refused to register type " + type_name);
  }
  Topic* t = participant_->create_topic(name, type_name, TOPIC_QOS_DEFAULT);
  if (!t) throw std::runtime_error("Fast DDS could not create topic " + name);
  topics_[name] = t;
  return t;
}

}  // namespace mcvio::dds::bench
