#pragma once
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <stdexcept>
#include <string>

#include "bare_participant.hpp"
#include "bare_qos.hpp"
#include "mcvio/interfaces/ros_type_traits.hpp"
#include "ping_pong.hpp"

namespace mcvio::dds::bench {

/// A DataReader with a listener that takes each sample into one reused instance and hands it to
/// `Derived::onSample`, written the way the Fast DDS examples do it.
template <class T, class Derived>
class BareReaderListener : public eprosima::fastdds::dds::DataReaderListener {
 public:
  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    eprosima::fastdds::dds::SampleInfo info;
    while (reader->take_next_sample(&sample_, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) static_cast<Derived*>(this)->onSample(sample_);
    }
  }

 private:
  T sample_;
};

/// Measuring end on bare Fast DDS: a DataWriter (ping) and a DataReader (pong) on the generated
/// PubSubType, with the same QoS as the wrapper's presets.
template <class T>
class BareProber : public Prober<T>, public BareReaderListener<T, BareProber<T>> {
 public:
  using PubSubType = typename interfaces::RosType<T>::PubSubType;

  BareProber(BareParticipant& participant, const std::string& ping_topic,
             const std::string& pong_topic)
      : participant_(participant) {
    auto* ping =
        participant.topic(ping_topic, eprosima::fastdds::dds::TypeSupport(new PubSubType()));
    auto* pong =
        participant.topic(pong_topic, eprosima::fastdds::dds::TypeSupport(new PubSubType()));
    reader_ = participant.subscriber()->create_datareader(
        pong, bareReaderQos<T>(QosProfile::defaults()), this);
    writer_ =
        participant.publisher()->create_datawriter(ping, bareWriterQos<T>(QosProfile::lossless()));
    if (!reader_ || !writer_)
      throw std::runtime_error("Fast DDS could not create the bare prober's endpoints");
  }
  ~BareProber() override {
    reader_->set_listener(nullptr);
    participant_.subscriber()->delete_datareader(reader_);
    participant_.publisher()->delete_datawriter(writer_);
  }

  bool send(const T& msg) override { return writer_->write(const_cast<T*>(&msg)); }

  void onSample(const T& msg) {
    this->monitor_.onPong(msg.header().stamp().nanosec(), msg.header().stamp().sec(),
                          msg.header().frame_id());
  }

 private:
  BareParticipant& participant_;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

/// Echo end on bare Fast DDS: the reader's listener writes the echo.
template <class T>
class BareEchoer : public Echoer, public BareReaderListener<T, BareEchoer<T>> {
 public:
  using PubSubType = typename interfaces::RosType<T>::PubSubType;

  BareEchoer(BareParticipant& participant, const std::string& ping_topic,
             const std::string& pong_topic)
      : participant_(participant) {
    auto* ping =
        participant.topic(ping_topic, eprosima::fastdds::dds::TypeSupport(new PubSubType()));
    auto* pong =
        participant.topic(pong_topic, eprosima::fastdds::dds::TypeSupport(new PubSubType()));
    writer_ =
        participant.publisher()->create_datawriter(pong, bareWriterQos<T>(QosProfile::defaults()));
    reader_ = participant.subscriber()->create_datareader(
        ping, bareReaderQos<T>(QosProfile::lossless()), this);
    if (!reader_ || !writer_)
      throw std::runtime_error("Fast DDS could not create the bare echo's endpoints");
  }
  ~BareEchoer() override {
    reader_->set_listener(nullptr);
    participant_.subscriber()->delete_datareader(reader_);
    participant_.publisher()->delete_datawriter(writer_);
  }

  void onSample(const T& msg) {
    rule_.onPing(msg, [this](const T& echo) { writer_->write(const_cast<T*>(&echo)); });
  }

 private:
  BareParticipant& participant_;
  EchoRule<T> rule_;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

}  // namespace mcvio::dds::bench
