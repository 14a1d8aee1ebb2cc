#pragma once
#include <string>

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"

namespace mcvio {

/// Loads a YAML file for an options or calibration reader. Throws mcvio::InputError naming the
/// file: "<path>: cannot open <what> (missing or unreadable)", "<path>:<line>: YAML syntax
/// error: ...", or "<path>:<line>: key 'k' appears twice ..." (see rejectDuplicateYamlKeys).
YAML::Node loadYamlFile(const std::string& path, const std::string& what);

/// The same for YAML text; `source` names where the text came from in messages.
YAML::Node parseYamlText(const std::string& text, const std::string& source);

/// yaml-cpp keeps both entries of a repeated map key and a lookup returns the first, so a second
/// `max_features: 300` further down a file would be ignored without a word. Throws
/// mcvio::InputError "<source>:<line>: key 'k' appears twice (first at line n)" for the first
/// repeated key found anywhere in the tree.
void rejectDuplicateYamlKeys(const YAML::Node& node, const std::string& source);

/// Loads an options file and parses it with `parse` (an Options::fromYaml): every error names the
/// file, and YAML syntax errors also the line.
template <class Parse>
auto loadOptionsFile(const std::string& path, Parse parse) {
  const YAML::Node node = loadYamlFile(path, "options file");
  try {
    return parse(node);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

}  // namespace mcvio
