#include "mcvio/core/topic_remapping.hpp"

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/ros_topic_name.hpp"

namespace mcvio {

TopicRemapping TopicRemapping::parse(const std::vector<std::string>& rules) {
  TopicRemapping remapping;
  for (const auto& rule : rules) {
    const auto sep = rule.find(":=");
    if (sep == std::string::npos) {
      throw InputError("remap rule '" + rule + "': expected FROM:=TO, e.g. /imu0:=/camera/imu");
    }
    try {
      remapping.add(std::string_view(rule).substr(0, sep), std::string_view(rule).substr(sep + 2));
    } catch (const InputError& e) {
      throw InputError("remap rule '" + rule + "': " + e.what());
    }
  }
  return remapping;
}

void TopicRemapping::add(std::string_view from, std::string_view to) {
  for (const auto name : {from, to}) {
    if (name.rfind("__", 0) == 0) {
      throw InputError("'" + std::string(name) + "' is a node-name or namespace rule; mcvio remaps topic names only");
    }
    if (name.find(':') != std::string_view::npos) {
      throw InputError("'" + std::string(name) + "' holds a ':'; node-specific rules (NODE:FROM:=TO) are not supported, "
                       "give the rule to that component");
    }
    const auto err = rosTopicNameError(name);
    if (!err.empty()) throw InputError("'" + std::string(name) + "': " + err);
  }
  const std::string abs_from = absoluteTopicName(from), abs_to = absoluteTopicName(to);
  for (const auto& r : rules_) {
    if (r.from == abs_from) {
      throw InputError(abs_from + " is remapped twice (to " + r.to + " and to " + abs_to + ")");
    }
  }
  rules_.push_back({abs_from, abs_to});
}

std::string TopicRemapping::resolve(std::string_view topic) const {
  std::string abs = absoluteTopicName(topic);
  for (const auto& r : rules_)
    if (r.from == abs) return r.to;
  return abs;
}

std::vector<std::string> TopicRemapping::toStrings() const {
  std::vector<std::string> out;
  for (const auto& r : rules_) out.push_back(r.from + ":=" + r.to);
  return out;
}

}  // namespace mcvio
