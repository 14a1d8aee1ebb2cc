#pragma once
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <map>
#include <memory>
#include <string>

#include "bench_transport.hpp"
#include "mcvio/dds/participant.hpp"

namespace mcvio::dds::bench {

/// Where bare DataWriters/DataReaders live: a plain Fast DDS DomainParticipant with one Publisher
/// and one Subscriber, what a user who does not use mcvio::dds writes by hand; or the native
/// entities of an mcvio::dds::Participant, so that wrapper and bare endpoints share the very same
/// receive threads and transports and differ only in the code between the application and Fast DDS.
class BareParticipant {
 public:
  /// An own participant. Throws std::runtime_error when Fast DDS refuses it.
  BareParticipant(int domain_id, const eprosima::fastdds::dds::DomainParticipantQos& qos);
  /// Borrows `host`'s DomainParticipant, Publisher and Subscriber (which must outlive this object);
  /// only the topics created here are deleted here.
  explicit BareParticipant(const Participant& host);
  ~BareParticipant();
  BareParticipant(const BareParticipant&) = delete;
  BareParticipant& operator=(const BareParticipant&) = delete;

  /// Registers `type` (once per name) and creates the topic (once per name).
  eprosima::fastdds::dds::Topic* topic(const std::string& name,
                                       eprosima::fastdds::dds::TypeSupport type);

  eprosima::fastdds::dds::DomainParticipant* native() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }

 private:
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  bool owns_participant_ = true;
};

/// The bare side's participant for `transport`: borrowed from `host` unless
/// `bus.bare_in_own_participant`.
std::unique_ptr<BareParticipant> makeBareParticipant(const BusConfig& bus, Transport transport,
                                                     const Participant& host,
                                                     const std::string& name);

}  // namespace mcvio::dds::bench
