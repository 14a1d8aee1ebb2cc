// mcvio: one command that fronts every component and tool.
#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "commands/command_context.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/dds/shutdown_signal.hpp"

namespace mcvio::cli {

dds::ParticipantOptions CommandContext::participantOptions(const std::string& name) const {
  if (!domain_given && !domain_env_error.empty()) throw CommandExit{2, domain_env_error};
  dds::ParticipantOptions o;
  o.domain_id = domain_id;
  o.profiles_file = profiles_file;
  o.profile_name = profile_name;
  o.name = name;
  return o;
}

}  // namespace mcvio::cli

int main(int argc, char** argv) {
  using namespace mcvio::cli;
  const std::vector<std::string> kLogLevels{"trace", "debug", "info", "warn", "error", "off"};
  // Log lines go to stderr, as ROS 2 nodes log: stdout stays for what a command prints (echo's YAML,
  // eval's tables), so it can be piped.
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("", std::make_shared<spdlog::sinks::stderr_color_sink_mt>()));
  CLI::App app{
      "mcvio: motion-conflict-aware stereo visual-inertial odometry on a ROS 2-compatible DDS bus.\n"
      "Topics and types are ordinary ROS 2 ones: `ros2 topic echo /mcvio/odometry` works alongside.\n\n"
      "Examples:\n"
      "  mcvio topics                      list topics on the bus with their ROS 2 types\n"
      "  mcvio echo /imu0 --count 1        print one message as YAML\n"
      "  mcvio nodes                       list ROS 2 nodes (mcvio components and others)\n"
      "  mcvio demo                        elevator + self-occlusion through the DDS components: reference vs MC-VIO\n"
      "  mcvio bus-demo                    publish and echo a short stream on the bus\n"
      "  mcvio sim --scenario elevator --out /tmp/elevator   render a sequence with a motion conflict\n"
      "  mcvio play /tmp/elevator --rate 2  publish a EuRoC folder on the bus\n"
      "  mcvio record -o /tmp/run --all     record the bus to a rosbag2 bag (MCAP)\n"
      "  mcvio calib DIR                   the stereo-inertial calibration as mcvio reads it (EuRoC or Kalibr)\n"
      "  mcvio frontend --calib DIR         stereo tracking on the bus: /mcvio/features\n"
      "  mcvio backend --calib DIR --mode auto   the estimator on the bus: /mcvio/odometry, /tf, /mcvio/conflict\n"
      "  mcvio launch config/pipeline.yaml data:=DIR   player + frontend + backend (+ recorder), one process or one each\n"
      "  mcvio run --dataset DIR --out OUT --mode auto   the whole VIO offline: trajectory.tum, conflict.csv, stats.json\n"
      "  mcvio eval --gt DIR --est OUT --out REPORT   ATE/RPE, detection ROC, plots against ground truth\n"
      "  mcvio bench --out DIR             the MC-VIO benchmark suite: every scenario and mode, one report",
      "mcvio"};
  app.require_subcommand(1);
  // Global options may also follow the command (`mcvio run ... --log-level debug`), as with
  // `ros2 run ... --ros-args --log-level debug`; subcommands inherit this.
  app.fallthrough();
  CommandContext ctx;
  if (const char* d = std::getenv("ROS_DOMAIN_ID"); d && *d) {
    char* end = nullptr;
    errno = 0;
    const long id = std::strtol(d, &end, 10);
    // Refused when a command joins the bus without --domain (participantOptions), as ROS 2 does;
    // the offline commands do not care.
    if (*end != '\0' || errno != 0 || id < 0 || id > 232)
      ctx.domain_env_error = std::string("ROS_DOMAIN_ID='") + d + "' is not a domain id (0..232); fix it or give --domain";
    else
      ctx.domain_id = static_cast<int>(id);
  }
  if (const char* p = std::getenv("MCVIO_DDS_PROFILES"); p && *p) ctx.profiles_file = p;
  auto* domain_option = app.add_option("--domain", ctx.domain_id,
                 "DDS domain id, 0..232 (default: $ROS_DOMAIN_ID or 0); must match the ROS 2 tools' domain")
      ->capture_default_str();
  app.add_option("--dds-profiles", ctx.profiles_file,
                 "Fast DDS XML profiles file, e.g. config/dds/localhost_only.xml (default: $MCVIO_DDS_PROFILES)");
  app.add_option("--dds-profile", ctx.profile_name,
                 "participant profile name inside --dds-profiles (default: the file's default profile)");
  if (const char* l = std::getenv("MCVIO_LOG_LEVEL"); l && *l) ctx.log_level = l;
  app.add_option("--log-level", ctx.log_level,
                 "log messages at this level and above: trace, debug, info, warn, error, off (default: "
                 "$MCVIO_LOG_LEVEL, else info; `bench` without --verbose: error). debug adds one line per "
                 "estimator frame (landmarks, residuals, solver iterations, biases, conflict state), e.g. "
                 "mcvio --log-level debug run --dataset DIR --out OUT -q 2> frames.log")
      ->check(CLI::IsMember(kLogLevels));
  // Runs after parsing, before the chosen command's callback: the level holds for all its work.
  app.parse_complete_callback([&app, &ctx, &kLogLevels, domain_option] {
    ctx.domain_given = domain_option->count() > 0;
    // The first SIGINT/SIGTERM asks for a clean stop (bags closed, the graph left, a run's files
    // marked unfinished) in the commands that poll for it; the others (sim, eval, bench, ...) keep
    // the default and end at once.
    for (const char* polling : {"play", "record", "echo", "frontend", "backend", "launch", "demo", "bus-demo", "run"})
      if (app.got_subcommand(polling)) mcvio::dds::ShutdownSignal::install();
    if (ctx.log_level.empty()) return;
    if (std::find(kLogLevels.begin(), kLogLevels.end(), ctx.log_level) == kLogLevels.end())
      throw CommandExit{2, "MCVIO_LOG_LEVEL: unknown level '" + ctx.log_level + "' (trace, debug, info, warn, error, off)"};
    spdlog::set_level(spdlog::level::from_str(ctx.log_level));
  });
  addTopicsCommand(app, ctx);
  addEvalCommand(app, ctx);
  addBenchCommand(app, ctx);
  addEchoCommand(app, ctx);
  addNodesCommand(app, ctx);
  addDemoCommand(app, ctx);
  addPlayCommand(app, ctx);
  addSimCommand(app, ctx);
  addInjectCommand(app, ctx);
  addRecordCommand(app, ctx);
  addBagCommand(app, ctx);
  addFrontendCommand(app, ctx);
  addBackendCommand(app, ctx);
  addRunCommand(app, ctx);
  addLaunchCommand(app, ctx);
  addCalibCommand(app, ctx);
  // CLI11 answers an unknown command with "A subcommand is required"; name it and the known ones.
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--domain" || arg == "--dds-profiles" || arg == "--dds-profile" || arg == "--log-level") {
      ++i;
      continue;
    }
    if (arg.empty() || arg[0] == '-') continue;
    std::string known;
    bool found = false;
    for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      found = found || sub->get_name() == arg;
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    if (found) break;
    std::cerr << "mcvio: unknown command '" << arg << "' (commands: " << known << "; mcvio --help explains them)\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const CommandExit& e) {
    if (!e.message.empty()) std::cerr << "mcvio: " << e.message << "\n";
    return e.code;
  } catch (const mcvio::InputError& e) {
    std::cerr << "mcvio: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "mcvio: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "mcvio: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
