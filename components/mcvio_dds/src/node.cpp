#include "mcvio/dds/node.hpp"

#include <stdexcept>

#include "mcvio/dds/topic_names.hpp"

namespace mcvio::dds {

Node::Node(std::shared_ptr<Participant> participant, std::string name, std::string ns)
    : participant_(std::move(participant)), name_(std::move(name)), ns_(std::move(ns)) {
  validateNodeName(name_);
  if (ns_.empty() || ns_.front() != '/') ns_ = "/" + ns_;
  if (ns_ != "/") validateTopicName(ns_);
  key_ = fullName();
  participant_->addEndpoint(key_, {}, false);  // an empty gid announces the node alone
}

Node::~Node() { participant_->removeNode(key_); }

std::string Node::fullName() const { return ns_ == "/" ? "/" + name_ : ns_ + "/" + name_; }

}  // namespace mcvio::dds
