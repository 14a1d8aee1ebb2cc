#pragma once
#include <cmath>
#include <set>
#include <string>

#include <Eigen/Core>
#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::sim::detail {

/// Reads optional keys of one YAML map, naming "<prefix><key>" in every error, and rejects keys
/// it was not asked about (a misspelt key must not be silently ignored).
class YamlFields {
 public:
  YamlFields(const YAML::Node& node, std::string prefix) : node_(node), prefix_(std::move(prefix)) {
    if (node_ && !node_.IsNull() && !node_.IsMap())
      throw InputError("option '" + name("") + "' must be a map");
  }

  std::string name(const std::string& key) const { return prefix_ + key; }

  template <typename T>
  void get(const std::string& key, T* value) {
    known_.insert(key);
    if (!node_ || node_.IsNull() || !node_[key]) return;
    try {
      *value = node_[key].as<T>();
    } catch (const YAML::Exception& e) {
      throw InputError("option '" + name(key) + "': cannot read value (" + e.msg + ")");
    }
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(*value)) throw InputError("option '" + name(key) + "' must be finite");
    }
  }

  void getVector3(const std::string& key, Eigen::Vector3d* value) {
    known_.insert(key);
    if (!node_ || node_.IsNull() || !node_[key]) return;
    const YAML::Node n = node_[key];
    if (!n.IsSequence() || n.size() != 3)
      throw InputError("option '" + name(key) + "' must be a list of 3 numbers");
    for (int i = 0; i < 3; ++i) {
      double v = 0;
      try {
        v = n[i].as<double>();
      } catch (const YAML::Exception& e) {
        throw InputError("option '" + name(key) + "': cannot read element " + std::to_string(i));
      }
      if (!std::isfinite(v)) throw InputError("option '" + name(key) + "' must be finite");
      (*value)[i] = v;
    }
  }

  YAML::Node child(const std::string& key) {
    known_.insert(key);
    if (!node_ || node_.IsNull()) return YAML::Node();
    return node_[key];
  }

  /// Throws for any key of the map that no get()/child() asked about.
  void rejectUnknown() const {
    if (!node_ || !node_.IsMap()) return;
    for (const auto& kv : node_) {
      const std::string key = kv.first.as<std::string>();
      if (!known_.count(key)) throw InputError("unknown option '" + name(key) + "'");
    }
  }

 private:
  const YAML::Node node_;
  std::string prefix_;
  std::set<std::string> known_;
};

/// Loads an options file and parses it with `parse` (an Options::fromYaml); every error names the
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

}  // namespace mcvio::sim::detail
