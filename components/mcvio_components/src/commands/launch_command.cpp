#include <unistd.h>

#include <iostream>
#include <map>

#include "commands/command_context.hpp"
#include "mcvio/components/launch_file.hpp"
#include "mcvio/components/launcher.hpp"

namespace mcvio::cli {

void addLaunchCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    std::string file;
    std::vector<std::string> assignments;
    bool show_args = false, quiet = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "launch",
      "Start a set of components together in this process, as a ROS 2 launch file with a component\n"
      "container does: players, frontends, backends and recorders named in a YAML launch file, each\n"
      "on a participant of its own (each is its own node in `mcvio nodes` / `ros2 node list`).\n"
      "Arguments declared in the file are given as NAME:=VALUE; --show-args lists them. The players\n"
      "start last, once the rest is listening. With a player (and exit_when_played, the default) the\n"
      "launch ends once it has played everything and the other components have handled it; without one\n"
      "it runs until Ctrl-C. Either way the backends are flushed and the bags closed: nothing received\n"
      "is lost. The same classes run as `mcvio play / frontend / backend / record` in separate\n"
      "processes; a lossless launch gives the poses of `mcvio run` on the same data.\n"
      "Examples:\n"
      "  mcvio launch config/pipeline.yaml data:=/tmp/elevator\n"
      "  mcvio launch config/pipeline.yaml data:=/tmp/elevator mode:=reference record:=true bag:=/tmp/rec lossless:=true\n"
      "  mcvio launch config/pipeline.yaml data:=/tmp/elevator play:=false    # live sensors on the bus\n"
      "  mcvio launch config/pipeline.yaml --show-args\n" +
          components::LaunchFile::keysHelp());
  cmd->add_option("file", opt->file, "launch file (YAML), e.g. config/pipeline.yaml")->required();
  cmd->add_option("arguments", opt->assignments, "NAME:=VALUE for the file's arguments, e.g. data:=/tmp/elevator");
  cmd->add_flag("--show-args", opt->show_args, "list the file's arguments (default, description) and exit");
  cmd->add_flag("-q,--quiet", opt->quiet, "no progress bars");
  cmd->callback([opt, &ctx] {
    const auto file = components::LaunchFile::load(opt->file);
    if (opt->show_args) {
      if (file.arguments().empty()) std::cout << opt->file << " declares no arguments\n";
      for (const auto& a : file.arguments()) {
        std::cout << "  " << a.name << ":=" << (a.has_default ? "'" + a.default_value + "'" : std::string("(required)"))
                  << "\n      " << (a.description.empty() ? "no description" : a.description) << "\n";
      }
      return;
    }
    std::map<std::string, std::string> values;
    for (const auto& text : opt->assignments) {
      const auto [name, value] = components::LaunchFile::parseAssignment(text);
      if (!values.emplace(name, value).second) throw CommandExit{2, "launch: argument '" + name + "' is given twice"};
    }
    auto plan = file.resolve(values);
    for (auto& e : plan.entries)
      if (opt->quiet || !isatty(STDERR_FILENO)) e.player.progress = false;
    components::Launcher launcher(std::move(plan), ctx.participantOptions("mcvio_launch"), &std::cerr);
    const auto result = launcher.run();
    std::cerr << "mcvio launch: " << opt->file << " done\n" << components::Launcher::summary(result);
    for (const auto& r : result.entries)
      if (!r.error.empty()) throw CommandExit{1, "launch: player '" + r.name + "' failed: " + r.error};
    if (result.interrupted) throw CommandExit{130, ""};
    if (!result.drained)
      throw CommandExit{1, "launch: the components had not handled everything the players published within "
                           "drain_timeout; raise it in the launch file"};
  });
}

}  // namespace mcvio::cli
