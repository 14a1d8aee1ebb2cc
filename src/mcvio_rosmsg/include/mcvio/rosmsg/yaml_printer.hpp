#pragma once
#include <cstddef>
#include <string>

#include "mcvio/rosmsg/message_value.hpp"

namespace mcvio::rosmsg {

/// Renders a decoded message as YAML, the way `ros2 topic echo` shows it.
struct YamlPrintOptions {
  /// Arrays longer than this print their first elements and a "... (N more)" line; 0 = all.
  std::size_t max_array_elements = 128;
};

std::string toYaml(const MessageValue& value, const YamlPrintOptions& options = {});

}  // namespace mcvio::rosmsg
