#include <chrono>
#include <iostream>
#include <unistd.h>

#include "commands/command_context.hpp"
#include "mcvio/dds/graph_monitor.hpp"
#include "mcvio/dds/node.hpp"

namespace mcvio::cli {

void addTopicsCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    double wait_s = 3.0;  // discovery of a new participant occasionally needs a SEDP repair (~3 s)
    bool verbose = false;
    bool all = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("topics",
                                 "List topics on the bus with their ROS 2 types, like `ros2 topic list -t`.\n"
                                 "Example: mcvio topics --verbose");
  cmd->add_option("--wait", opt->wait_s, "seconds to listen for discovery before printing")
      ->check(finiteAtLeastZero())
      ->check(CLI::Range(0.0, 86400.0))
      ->capture_default_str();
  cmd->add_flag("-v,--verbose", opt->verbose, "also print publisher/subscriber counts, offered QoS and type hash");
  cmd->add_flag("-a,--all", opt->all, "include DDS topics that are not ROS 2 topics (e.g. ros_discovery_info)");
  cmd->callback([opt, &ctx] {
    dds::GraphMonitor monitor;
    auto participant = dds::Participant::create(ctx.participantOptions("mcvio_topics"), &monitor);
    auto node = participant->createNode("_mcvio_topics_" + std::to_string(getpid()));
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(opt->wait_s * 1000)));
    for (const auto& t : monitor.topics()) {
      if (!t.is_ros && !opt->all) continue;
      std::cout << t.name << " [" << t.type << "]\n";
      if (opt->verbose) {
        std::cout << "    publishers: " << t.publishers << ", subscribers: " << t.subscribers << "\n";
        for (const auto& q : t.publisher_qos) std::cout << "    offered: " << q.describe() << "\n";
        if (!t.type_hash.empty()) std::cout << "    type hash: " << t.type_hash << "\n";
      }
    }
  });
}

}  // namespace mcvio::cli
