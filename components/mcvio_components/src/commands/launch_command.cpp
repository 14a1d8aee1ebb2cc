#include <unistd.h>

#include <iostream>
#include <map>

#include "commands/command_context.hpp"
#include "mcvio/components/launch_file.hpp"
#include "mcvio/components/launch_supervisor.hpp"
#include "mcvio/components/launcher.hpp"

namespace mcvio::cli {

namespace {

struct LaunchOptions {
  std::string file;
  std::vector<std::string> assignments;
  bool show_args = false, quiet = false, processes = false;
  std::string node;  ///< set by --processes in each child: run only this component
};

/// The plan of one component of `plan` (`--node NAME`). A player also waits, on each topic, for
/// a reader of every recorder of the plan that records it: those run in processes of their own
/// and must have subscribed before it plays.
components::LaunchPlan onlyNode(components::LaunchPlan plan, const std::string& name) {
  std::vector<components::RecorderOptions> recorders;
  for (const auto& e : plan.entries)
    if (e.kind == components::LaunchPlan::Kind::kRecorder) recorders.push_back(e.recorder);
  std::vector<components::LaunchPlan::Entry> kept;
  for (auto& e : plan.entries)
    if (e.name == name) kept.push_back(std::move(e));
  if (kept.empty()) throw CommandExit{2, "launch: " + plan.source + " starts no component '" + name + "'"};
  if (kept.front().kind == components::LaunchPlan::Kind::kPlayer && !recorders.empty())
    kept.front().player.extra_readers = [recorders](const std::string& topic) {
      int n = 0;
      for (const auto& r : recorders) n += r.selects(topic) ? 1 : 0;
      return n;
    };
  plan.entries = std::move(kept);
  return plan;
}

/// --processes: this process supervises one child per component (this program, `--node NAME`).
void runInProcesses(components::LaunchPlan plan, const LaunchOptions& opt, const CommandContext& ctx) {
  std::vector<std::string> base{"/proc/self/exe"};
  if (ctx.domain_given) base.insert(base.end(), {"--domain", std::to_string(ctx.domain_id)});
  if (!ctx.profiles_file.empty()) base.insert(base.end(), {"--dds-profiles", ctx.profiles_file});
  if (!ctx.profile_name.empty()) base.insert(base.end(), {"--dds-profile", ctx.profile_name});
  if (!ctx.log_level.empty()) base.insert(base.end(), {"--log-level", ctx.log_level});
  base.insert(base.end(), {"launch", opt.file});
  base.insert(base.end(), opt.assignments.begin(), opt.assignments.end());
  if (opt.quiet) base.push_back("-q");
  // Each child resolves the file again with these arguments, so it gets the same plan.
  ctx.participantOptions("mcvio_launch");  // refuses a bad $ROS_DOMAIN_ID here, not in every child
  const auto command = [&base](const components::LaunchPlan::Entry& e) {
    auto argv = base;
    argv.insert(argv.end(), {"--node", e.name});
    return argv;
  };
  const std::string source = plan.source;
  components::LaunchSupervisor supervisor(std::move(plan), command, {}, &std::cerr);
  const auto result = supervisor.run();
  std::cerr << "mcvio launch: " << source << " done (one process per component)\n"
            << components::LaunchSupervisor::summary(result);
  if (result.interrupted) throw CommandExit{130, ""};
  if (!result.error.empty()) throw CommandExit{1, "launch: " + result.error};
}

}  // namespace

void addLaunchCommand(CLI::App& app, CommandContext& ctx) {
  using Options = LaunchOptions;
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "launch",
      "Start a set of components together, as a ROS 2 launch file does: players, frontends, backends\n"
      "and recorders named in a YAML launch file, each on a participant of its own (each is its own\n"
      "node in `mcvio nodes` / `ros2 node list`). By default they run in this process, as in a ROS 2\n"
      "component container; with --processes each runs in a process of its own (one crash ends only\n"
      "that process, and the launch stops the rest cleanly).\n"
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
      "  mcvio launch config/pipeline.yaml data:=/tmp/elevator --processes   # one process per component\n"
      "  mcvio launch config/pipeline.yaml data:=/tmp/elevator --processes respawn:=true   # crashed ones restart\n"
      "  mcvio launch config/pipeline.yaml --show-args\n" +
          components::LaunchFile::keysHelp());
  cmd->add_option("file", opt->file, "launch file (YAML), e.g. config/pipeline.yaml")->required();
  cmd->add_option("arguments", opt->assignments, "NAME:=VALUE for the file's arguments, e.g. data:=/tmp/elevator");
  cmd->add_flag("--show-args", opt->show_args, "list the file's arguments (default, description) and exit");
  cmd->add_flag("-q,--quiet", opt->quiet, "no progress bars");
  cmd->add_flag("--processes", opt->processes,
                "run each component in a process of its own (`mcvio launch FILE ... --node NAME`), players "
                "last; once they have exited the rest stop in the order data flows, each after handling "
                "its queue; Ctrl-C stops them all, bags closed; a frontend or backend with 'respawn: true' that "
                "ends meanwhile is started again");
  cmd->add_option("--node", opt->node,
                  "run only the component NAME of the file (what --processes starts in each process), e.g. "
                  "--node backend");
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
    if (opt->processes && opt->node.empty()) {
      runInProcesses(std::move(plan), *opt, ctx);
      return;
    }
    if (opt->node.empty())
      for (const auto& e : plan.entries)
        if (e.respawn)
          std::cerr << "mcvio launch: " << components::LaunchPlan::kindName(e.kind) << " '" << e.name
                    << "' has 'respawn', which takes --processes (in one process a crash ends the launch); ignored\n";
    components::Launcher::Control control;
    if (!opt->node.empty()) {
      plan = onlyNode(std::move(plan), opt->node);
      control.started = [] { components::LaunchSupervisor::notifyStarted(); };
      control.data_ended = [] { return components::LaunchSupervisor::stopRequestedByParent(); };
    }
    components::Launcher launcher(std::move(plan), ctx.participantOptions("mcvio_launch"), &std::cerr);
    const auto result = launcher.run(control);
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
