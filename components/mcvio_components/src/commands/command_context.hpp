#pragma once
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mcvio/dds/node.hpp"
#include "mcvio/dds/participant.hpp"

namespace mcvio::cli {

/// Options every subcommand shares: which DDS domain and profile to join, how much to log.
struct CommandContext {
  int domain_id = 0;
  bool domain_given = false;     ///< --domain on the command line (it overrides $ROS_DOMAIN_ID)
  std::string domain_env_error;  ///< why $ROS_DOMAIN_ID is unusable, if it is
  std::string profiles_file;
  std::string profile_name;
  /// spdlog level name from --log-level or $MCVIO_LOG_LEVEL; empty: the command's default.
  std::string log_level;

  /// ParticipantOptions for a participant of this command (validated when created).
  dds::ParticipantOptions participantOptions(const std::string& name) const;
};

/// Each subcommand adds itself to the app; the callback runs when it is chosen.
void addTopicsCommand(CLI::App& app, CommandContext& ctx);
void addEvalCommand(CLI::App& app, CommandContext& ctx);
void addBenchCommand(CLI::App& app, CommandContext& ctx);
void addEchoCommand(CLI::App& app, CommandContext& ctx);
void addNodesCommand(CLI::App& app, CommandContext& ctx);
void addDemoCommand(CLI::App& app, CommandContext& ctx);
void addPlayCommand(CLI::App& app, CommandContext& ctx);
void addSimCommand(CLI::App& app, CommandContext& ctx);
void addInjectCommand(CLI::App& app, CommandContext& ctx);
void addRecordCommand(CLI::App& app, CommandContext& ctx);
void addBagCommand(CLI::App& app, CommandContext& ctx);
void addFrontendCommand(CLI::App& app, CommandContext& ctx);
void addBackendCommand(CLI::App& app, CommandContext& ctx);
void addRunCommand(CLI::App& app, CommandContext& ctx);
void addLaunchCommand(CLI::App& app, CommandContext& ctx);
void addCalibCommand(CLI::App& app, CommandContext& ctx);

/// CLI11's NonNegativeNumber lets NaN through (NaN < 0 is false): a finite number >= 0 (or > 0).
inline CLI::Validator finiteAtLeastZero(bool zero_allowed = true) {
  return CLI::Validator(
      [zero_allowed](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (!std::isfinite(v) || v < 0 || (!zero_allowed && v == 0))
          return "'" + text + "' must be a finite number " + (zero_allowed ? ">= 0" : "> 0");
        return {};
      },
      zero_allowed ? "NUMBER >= 0" : "NUMBER > 0");
}

/// `--remap FROM:=TO` (repeatable): ROS 2 topic remapping for the component the command runs.
inline CLI::Option* addRemapOption(CLI::App* cmd, std::vector<std::string>& rules, const std::string& example) {
  return cmd->add_option("--remap", rules,
                         "FROM:=TO: use topic TO wherever this component would use FROM (ROS 2's remapping, as\n"
                         "`ros2 run ... --ros-args -r FROM:=TO`); repeat for more topics, e.g.\n  --remap " + example)
      ->type_name("FROM:=TO")
      ->take_all()
      ->allow_extra_args(false);
}

/// A remap rule that matched none of the component's topics does nothing: most likely a typo.
inline void warnUnusedRemapRules(const dds::Node& node, const std::string& command) {
  for (const auto& rule : node.unusedRemapRules())
    std::cerr << "mcvio " << command << ": warning: --remap " << rule << " matches none of its topics\n";
}

/// Thrown by a command to end with `code` after printing `what()` (if not empty) to stderr.
struct CommandExit {
  int code;
  std::string message;
};

}  // namespace mcvio::cli
