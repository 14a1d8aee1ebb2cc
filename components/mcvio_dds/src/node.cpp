#include "mcvio/dds/node.hpp"

#include <stdexcept>

#include "mcvio/core/ros_topic_name.hpp"
#include "mcvio/dds/topic_names.hpp"

namespace mcvio::dds {

Node::Node(std::shared_ptr<Participant> participant, std::string name, std::string ns, TopicRemapping remapping)
    : participant_(std::move(participant)), name_(std::move(name)), ns_(std::move(ns)), remapping_(std::move(remapping)) {
  validateNodeName(name_);
  if (ns_.empty() || ns_.front() != '/') ns_ = "/" + ns_;
  if (ns_ != "/") validateTopicName(ns_);
  key_ = fullName();
  participant_->addEndpoint(key_, {}, false);  // an empty gid announces the node alone
}

Node::~Node() { participant_->removeNode(key_); }

std::string Node::resolveTopic(std::string_view topic) const {
  const std::string abs = absoluteTopicName(topic);
  std::lock_guard<std::mutex> lock(asked_mutex_);
  asked_.insert(abs);
  return remapping_.resolve(abs);
}

bool Node::remapByDefault(std::string_view from, std::string_view to) {
  std::lock_guard<std::mutex> lock(asked_mutex_);
  const std::string abs = absoluteTopicName(from);
  for (const auto& r : remapping_.rules())
    if (r.from == abs) return false;
  remapping_.add(abs, to);
  return true;
}

std::vector<std::string> Node::unusedRemapRules() const {
  std::lock_guard<std::mutex> lock(asked_mutex_);
  std::vector<std::string> unused;
  for (const auto& r : remapping_.rules())
    if (!asked_.count(r.from)) unused.push_back(r.from + ":=" + r.to);
  return unused;
}

std::string Node::fullName() const { return ns_ == "/" ? "/" + name_ : ns_ + "/" + name_; }

}  // namespace mcvio::dds
