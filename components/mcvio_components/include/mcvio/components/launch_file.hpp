#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mcvio/components/launch_plan.hpp"

namespace mcvio::components {

/// A launch file: the components `mcvio launch` starts together in one process (like a ROS 2
/// launch file with a component container), with arguments given at launch as NAME:=VALUE.
///
///   arguments:                      # NAME: {default: VALUE, description: TEXT}
///     data: {description: "EuRoC folder: the calibration, and what the player plays"}
///     mode: {default: auto, description: "reference, imu, selective or auto"}
///   exit_when_played: true          # stop once the players are done and the rest has caught up
///   drain_timeout: 120              # [s] to wait for that
///   components:                     # started in this order, stopped in reverse
///     - component: backend          # player, frontend, backend or recorder
///       calibration: $(arg data)
///       mode: $(arg mode)
///     - component: player
///       if: $(arg play)             # `if` / `unless`: true or false once substituted
///       input: $(arg data)
///
/// Substitutions, in any value: `$(arg NAME)`, `$(env NAME)`, `$(env NAME DEFAULT)` and
/// `$(dirname)` (the folder of the launch file). An argument without a default must be given.
/// Each kind's keys mirror its command's options (`mcvio launch --help` lists them).
class LaunchFile {
 public:
  struct Argument {
    std::string name, description, default_value;
    bool has_default = false;
  };

  /// Throws mcvio::InputError naming the file (and the line) for a missing file, a YAML syntax
  /// error or a malformed `arguments:` section. The components are checked by resolve().
  static LaunchFile load(const std::string& path);
  /// The same for YAML text; `source` names it in messages, `dirname` is what $(dirname) gives.
  static LaunchFile parse(const std::string& text, const std::string& source, const std::string& dirname);

  const std::string& source() const { return source_; }
  const std::vector<Argument>& arguments() const { return arguments_; }

  /// Substitutes `values` (NAME -> VALUE, from NAME:=VALUE) and the defaults, and builds the plan.
  /// Throws mcvio::InputError "<file>:<line>: ..." for an argument that is not declared or not
  /// given, an unknown substitution, component kind or key, a bad value, duplicate node names.
  LaunchPlan resolve(const std::map<std::string, std::string>& values) const;

  /// "NAME:=VALUE" -> {NAME, VALUE}; throws mcvio::InputError for anything else.
  static std::pair<std::string, std::string> parseAssignment(const std::string& text);
  /// The keys each kind takes, for --help.
  static std::string keysHelp();

 private:
  using Values = std::map<std::string, std::string>;
  std::string substitute(const std::string& text, const Values& args, const YAML::Node& where) const;
  YAML::Node substituted(const YAML::Node& node, const Values& args) const;
  LaunchPlan::Entry entry(const YAML::Node& node, std::size_t index, const Values& args) const;
  void readArguments();
  std::string at(const YAML::Node& node) const;  ///< "<file>:<line>: "
  std::string declaredNames() const;             ///< "data, mode" (or "none"), for messages

  std::string source_, dirname_;
  YAML::Node root_;
  std::vector<Argument> arguments_;
};

}  // namespace mcvio::components
