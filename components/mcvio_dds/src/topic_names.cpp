#include "mcvio/dds/topic_names.hpp"

#include <cctype>
#include <stdexcept>

#include "mcvio/core/ros_topic_name.hpp"

namespace mcvio::dds {

std::string topicNameError(std::string_view name) { return rosTopicNameError(name); }

void validateTopicName(std::string_view name) {
  const auto err = topicNameError(name);
  if (!err.empty()) throw std::invalid_argument("invalid topic name '" + std::string(name) + "': " + err);
}

void validateNodeName(std::string_view name) {
  std::string err;
  if (name.empty()) {
    err = "node name is empty";
  } else if (std::isdigit(static_cast<unsigned char>(name[0]))) {
    err = "node name must not start with a digit";
  } else {
    for (char c : name) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') {
        err = std::string("node name contains '") + c + "' (allowed: letters, digits, '_')";
        break;
      }
    }
  }
  if (!err.empty()) throw std::invalid_argument("invalid node name '" + std::string(name) + "': " + err);
}

std::string toDdsTopicName(std::string_view ros_topic) {
  validateTopicName(ros_topic);
  return "rt" + absoluteTopicName(ros_topic);
}

std::optional<std::string> toRosTopicName(std::string_view dds_topic) {
  if (dds_topic.size() < 4 || dds_topic.substr(0, 3) != "rt/") return std::nullopt;
  return std::string(dds_topic.substr(2));
}

}  // namespace mcvio::dds
