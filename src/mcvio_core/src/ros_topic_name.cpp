#include "mcvio/core/ros_topic_name.hpp"

#include <cctype>

namespace mcvio {
namespace {

// rmw limits a ROS topic so that "rt" + name fits DDS's 256-character topic names with room for
// the service suffixes.
constexpr std::size_t kMaxTopicLength = 247;

}  // namespace

std::string rosTopicNameError(std::string_view name) {
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

std::string absoluteTopicName(std::string_view name) {
  if (!name.empty() && name.front() == '/') return std::string(name);
  return "/" + std::string(name);
}

}  // namespace mcvio
