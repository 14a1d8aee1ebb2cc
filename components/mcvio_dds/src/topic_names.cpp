#include "mcvio/dds/topic_names.hpp"

#include <cctype>
#include <stdexcept>

namespace mcvio::dds {
namespace {

// rmw limits a ROS topic so that "rt" + name fits DDS's 256-character topic names with room for
// the service suffixes.
constexpr std::size_t kMaxTopicLength = 247;

}  // namespace

std::string topicNameError(std::string_view name) {
  if (name.empty()) return "topic name is empty";
  if (name.size() > kMaxTopicLength) {
    return "topic name is longer than " + std::to_string(kMaxTopicLength) + " characters";
  }
  if (name.size() > 1 && name.back() == '/') return "topic name must not end with '/'";
  if (name == "/") return "topic name '/' has no tokens";
  bool token_start = true;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (c == '/') {
      if (i > 0 && name[i - 1] == '/') return "topic name must not contain '//'";
      token_start = true;
      continue;
    }
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') {
      return std::string("topic name contains '") + c + "' at position " + std::to_string(i) +
             " (allowed: letters, digits, '_' and '/')";
    }
    if (token_start && std::isdigit(static_cast<unsigned char>(c))) {
      return "a topic name token must not start with a digit (position " + std::to_string(i) + ")";
    }
    token_start = false;
  }
  return {};
}

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
  return ros_topic.front() == '/' ? "rt" + std::string(ros_topic) : "rt/" + std::string(ros_topic);
}

std::optional<std::string> toRosTopicName(std::string_view dds_topic) {
  if (dds_topic.size() < 4 || dds_topic.substr(0, 3) != "rt/") return std::nullopt;
  return std::string(dds_topic.substr(2));
}

}  // namespace mcvio::dds
