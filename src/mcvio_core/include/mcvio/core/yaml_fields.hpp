#pragma once
#include <cmath>
#include <set>
#include <string>
#include <type_traits>

#include <Eigen/Core>
#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"

namespace mcvio {

/// Reads the optional keys of one YAML map into options fields: every options reader of mcvio
/// goes through it, so they all report the same way. Errors name "<what> '<prefix><key>'" (what:
/// "estimator option", "key", ...); a value of the wrong type or a non-finite number is an error;
/// rejectUnknown() throws for any key of the map that no get()/child() asked about (a misspelt key
/// would otherwise keep its default without a word). A null or missing node reads as empty.
class YamlFields {
 public:
  /// Throws mcvio::InputError if `node` is neither null nor a map.
  YamlFields(const YAML::Node& node, std::string prefix, std::string what = "option");

  /// "<prefix><key>", as errors name it.
  std::string name(const std::string& key) const { return prefix_ + key; }
  /// The key is present (and marks it known).
  bool has(const std::string& key);

  /// Leaves `value` alone when the key is absent.
  template <typename T>
  void get(const std::string& key, T* value) {
    YAML::Node v;
    if (!lookUp(key, &v)) return;
    try {
      *value = v.as<T>();
    } catch (const YAML::Exception& e) {
      throw InputError(what_ + " '" + name(key) + "' has an invalid value '" + text(v) + "' (" + e.msg + ")");
    }
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(*value)) throw InputError(what_ + " '" + name(key) + "' must be finite");
    }
  }
  /// A list of three finite numbers.
  void getVector3(const std::string& key, Eigen::Vector3d* value);
  /// The nested node (null when absent); its keys are the caller's to check.
  YAML::Node child(const std::string& key);
  /// Throws for the first key of the map that no get()/has()/child() asked about.
  void rejectUnknown() const;

 private:
  /// Marks the key known; false when it is absent.
  bool lookUp(const std::string& key, YAML::Node* value);
  static std::string text(const YAML::Node& v);

  YAML::Node node_;
  std::string prefix_;
  std::string what_;
  std::set<std::string> known_;
};

/// Throws mcvio::InputError "<what> '<key>' <rule> (got <value>)" unless `ok` holds and `value`
/// is finite: the options structs' validate().
void requireOption(bool ok, const std::string& what, const std::string& key, const std::string& rule, double value);
/// The same for a rule that no single value shows: "<what> '<key>' <rule>".
void requireOption(bool ok, const std::string& what, const std::string& key, const std::string& rule);

}  // namespace mcvio
