#pragma once
#include <chrono>
#include <memory>
#include <string>

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "mcvio/dds/qos_profile.hpp"

namespace mcvio::dds {

class Node;

/// True while this thread runs a subscription callback. A keep-all write from there must not wait
/// for acknowledgments: the thread that would process them is this one (it would hang forever).
bool& inSubscriptionCallback();

/// Marks the current thread as running a subscription callback for its lifetime.
class SubscriptionCallbackScope {
 public:
  SubscriptionCallbackScope() : previous_(inSubscriptionCallback()) { inSubscriptionCallback() = true; }
  ~SubscriptionCallbackScope() { inSubscriptionCallback() = previous_; }
  SubscriptionCallbackScope(const SubscriptionCallbackScope&) = delete;
  SubscriptionCallbackScope& operator=(const SubscriptionCallbackScope&) = delete;

 private:
  bool previous_;
};

/// The untyped part of a publisher: topic, DataWriter, ROS graph bookkeeping.
class WriterEndpoint {
 public:
  WriterEndpoint(Node& node, const std::string& ros_topic, eprosima::fastdds::dds::TypeSupport type,
                 const std::string& type_hash, const QosProfile& qos);
  virtual ~WriterEndpoint();
  WriterEndpoint(const WriterEndpoint&) = delete;
  WriterEndpoint& operator=(const WriterEndpoint&) = delete;

  const std::string& topic() const { return ros_topic_; }
  const QosProfile& qos() const { return qos_; }
  /// Number of matched readers right now.
  int matchedReaders() const;
  /// Waits until at least `count` readers matched; false on timeout.
  bool waitForReaders(int count, std::chrono::milliseconds timeout) const;
  /// Waits until every matched reliable reader acknowledged all samples; false on timeout.
  bool waitForAcknowledgments(std::chrono::milliseconds timeout) const;
  /// Writes one sample (type-erased pointer of the registered type). With the lossless profile
  /// a full reader makes this wait; it retries until written or `give_up` passes, returning false.
  /// Inside a subscription callback it tries once (see inSubscriptionCallback()): lossless
  /// republishing belongs on the component's own thread.
  bool write(void* sample, std::chrono::milliseconds give_up = std::chrono::milliseconds(60000));

 protected:
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;

 private:
  std::shared_ptr<Node> node_;
  std::string ros_topic_;
  QosProfile qos_;
  eprosima::fastdds::dds::Topic* topic_ = nullptr;
};

/// The untyped part of a subscription: topic, DataReader with a listener, graph bookkeeping.
class ReaderEndpoint {
 public:
  ReaderEndpoint(Node& node, const std::string& ros_topic, eprosima::fastdds::dds::TypeSupport type,
                 const std::string& type_hash, const QosProfile& qos);
  virtual ~ReaderEndpoint();
  ReaderEndpoint(const ReaderEndpoint&) = delete;
  ReaderEndpoint& operator=(const ReaderEndpoint&) = delete;

  const std::string& topic() const { return ros_topic_; }
  int matchedWriters() const;

 protected:
  /// Creates the DataReader; derived classes call it at the end of their constructor, once the
  /// listener is ready for samples.
  void start(eprosima::fastdds::dds::DataReaderListener* listener);
  /// Stops callbacks; derived classes call it first in their destructor so the listener never
  /// sees a half-destroyed object.
  void shutdown();
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;

 private:
  std::shared_ptr<Node> node_;
  std::string ros_topic_;
  eprosima::fastdds::dds::Topic* topic_ = nullptr;
  eprosima::fastdds::dds::DataReaderQos reader_qos_;
};

}  // namespace mcvio::dds
