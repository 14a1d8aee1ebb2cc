#include <chrono>
#include <iostream>
#include <thread>
#include <unistd.h>

#include "commands/command_context.hpp"
#include "mcvio/dds/graph_monitor.hpp"
#include "mcvio/dds/node.hpp"

namespace mcvio::cli {

void addNodesCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    double wait_s = 3.0;  // discovery of a new participant occasionally needs a SEDP repair (~3 s)
    bool all = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("nodes",
                                 "List ROS 2 nodes announced on the bus (ros_discovery_info), like `ros2 node list`.\n"
                                 "Example: mcvio nodes --wait 3");
  cmd->add_option("--wait", opt->wait_s, "seconds to listen before printing")
      ->check(finiteAtLeastZero())
      ->check(CLI::Range(0.0, 86400.0))
      ->capture_default_str();
  cmd->add_flag("-a,--all", opt->all, "include hidden nodes (names starting with '_', like this tool's own)");
  cmd->callback([opt, &ctx] {
    dds::GraphMonitor monitor;
    auto participant = dds::Participant::create(ctx.participantOptions("mcvio_nodes"), &monitor);
    auto node = participant->createNode("_mcvio_nodes_" + std::to_string(getpid()));
    monitor.watchNodes(*node);
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(opt->wait_s * 1000)));
    for (const auto& n : monitor.nodes()) {
      if (!opt->all && !n.name.empty() && n.name.front() == '_') continue;
      std::cout << n.fullName() << "\n";
    }
  });
}

}  // namespace mcvio::cli
