#pragma once
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "mcvio/core/topic_remapping.hpp"

#include "mcvio/dds/participant.hpp"
#include "mcvio/dds/qos_profile.hpp"

namespace mcvio::dds {

template <class T> class Publisher;
template <class T> class Subscription;
class GenericPublisher;
class GenericSubscription;
struct ReceivedPayload;

/// A ROS 2 node: a name under which publishers and subscriptions appear in the ROS graph.
/// Components (frontend, backend, ...) each own one; several may share a Participant.
/// Always held by shared_ptr (Participant::createNode): its publishers and subscriptions keep it alive.
class Node : public std::enable_shared_from_this<Node> {
 public:
  /// `remapping`: the node's topic remap rules (`-r FROM:=TO`), applied to every ROS topic its
  /// publishers and subscriptions name.
  Node(std::shared_ptr<Participant> participant, std::string name, std::string ns, TopicRemapping remapping = {});
  ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  const std::string& name() const { return name_; }
  const std::string& ns() const { return ns_; }
  /// "/ns/name", as `ros2 node list` prints it.
  std::string fullName() const;
  const std::shared_ptr<Participant>& participant() const { return participant_; }
  const std::string& key() const { return key_; }

  /// The topic a publisher or subscription of this node asking for `topic` uses (remapped).
  std::string resolveTopic(std::string_view topic) const;
  const TopicRemapping& remapping() const { return remapping_; }
  /// Rules whose FROM no publisher or subscription of this node has asked for so far, as
  /// "FROM:=TO" (a mistyped rule does nothing, so components warn about these once set up).
  std::vector<std::string> unusedRemapRules() const;
  /// Adds FROM:=TO unless the node already has a rule for FROM (the user's rule wins); returns
  /// whether it did. For a default a component learns once it has its node, such as the topics a
  /// calibration names; call it before creating the endpoints it should apply to.
  bool remapByDefault(std::string_view from, std::string_view to);

  /// Typed publisher of a generated ROS 2 type (see mcvio/interfaces/ros_type_traits.hpp).
  template <class T>
  std::unique_ptr<Publisher<T>> createPublisher(const std::string& topic, const QosProfile& qos);
  /// Typed subscription; `callback` runs on a Fast DDS thread for every sample.
  template <class T>
  std::unique_ptr<Subscription<T>> createSubscription(const std::string& topic, const QosProfile& qos,
                                                      std::function<void(const T&)> callback);

 private:
  std::shared_ptr<Participant> participant_;
  std::string name_, ns_, key_;
  TopicRemapping remapping_;
  mutable std::mutex asked_mutex_;
  mutable std::set<std::string> asked_;  ///< topics asked for, before remapping
};

}  // namespace mcvio::dds

#include "mcvio/dds/publisher.hpp"
#include "mcvio/dds/subscription.hpp"

namespace mcvio::dds {

template <class T>
std::unique_ptr<Publisher<T>> Node::createPublisher(const std::string& topic, const QosProfile& qos) {
  return std::make_unique<Publisher<T>>(*this, topic, qos);
}

template <class T>
std::unique_ptr<Subscription<T>> Node::createSubscription(const std::string& topic, const QosProfile& qos,
                                                          std::function<void(const T&)> callback) {
  return std::make_unique<Subscription<T>>(*this, topic, qos, std::move(callback));
}

}  // namespace mcvio::dds
