#pragma once
#include <string>
#include <string_view>

namespace mcvio {

/// ROS 2 topic name rules (rcl's), shared by the DDS layer and by what reads bags offline.
/// Returns an empty string when `name` is a valid topic name ("/a/b", or relative "a/b", which
/// mcvio takes as "/a/b"), otherwise a sentence saying what is wrong.
std::string rosTopicNameError(std::string_view name);

/// "a/b" -> "/a/b"; a name that already starts with '/' is returned as it is.
std::string absoluteTopicName(std::string_view name);

}  // namespace mcvio
