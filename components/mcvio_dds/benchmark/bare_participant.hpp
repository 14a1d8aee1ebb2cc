#pragma once
#include <map>
#include <string>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

namespace mcvio::dds::bench {

/// A plain Fast DDS DomainParticipant with one Publisher and one Subscriber: what a user who does
/// not use mcvio::dds writes by hand. The benchmark's reference for the wrapper's overhead.
class BareParticipant {
 public:
  /// Throws std::runtime_error when Fast DDS refuses the participant.
  BareParticipant(int domain_id, const eprosima::fastdds::dds::DomainParticipantQos& qos);
  ~BareParticipant();
  BareParticipant(const BareParticipant&) = delete;
  BareParticipant& operator=(const BareParticipant&) = delete;

  /// Registers `type` (once per name) and creates the topic (once per name).
  eprosima::fastdds::dds::Topic* topic(const std::string& name, eprosima::fastdds::dds::TypeSupport type);

  eprosima::fastdds::dds::DomainParticipant* native() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }

 private:
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
};

}  // namespace mcvio::dds::bench
