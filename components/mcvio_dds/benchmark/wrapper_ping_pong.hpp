#pragma once
#include <memory>
#include <string>

#include "mcvio/dds/node.hpp"
#include "ping_pong.hpp"

namespace mcvio::dds::bench {

/// Measuring end on mcvio::dds: Node::createPublisher (ping) and Node::createSubscription (pong).
template <class T>
class WrapperProber : public Prober<T> {
 public:
  WrapperProber(Node& node, const std::string& ping_topic, const std::string& pong_topic)
      : pong_(node.createSubscription<T>(pong_topic, QosProfile::defaults(),
                                         [this](const T& msg) {
                                           this->monitor_.onPong(msg.header().stamp().nanosec(),
                                                                 msg.header().stamp().sec(),
                                                                 msg.header().frame_id());
                                         })),
        ping_(node.createPublisher<T>(ping_topic, QosProfile::lossless())) {}

  // The wrapper already retries a blocked keep-all write until its give-up time.
  bool send(const T& msg) override { return ping_->publish(msg); }

 private:
  std::unique_ptr<Subscription<T>> pong_;
  std::unique_ptr<Publisher<T>> ping_;
};

/// Echo end on mcvio::dds: the subscription's callback publishes the echo.
template <class T>
class WrapperEchoer : public Echoer {
 public:
  WrapperEchoer(Node& node, const std::string& ping_topic, const std::string& pong_topic)
      : pong_(node.createPublisher<T>(pong_topic, QosProfile::defaults())),
        ping_(node.createSubscription<T>(ping_topic, QosProfile::lossless(), [this](const T& msg) {
          rule_.onPing(msg, [this](const T& echo) { pong_->publish(echo); });
        })) {}

 private:
  EchoRule<T> rule_;
  std::unique_ptr<Publisher<T>> pong_;
  std::unique_ptr<Subscription<T>> ping_;
};

}  // namespace mcvio::dds::bench
