#include <atomic>
#include <chrono>
#include <iostream>
#include <mutex>
#include <thread>
#include <unistd.h>

#include "commands/command_context.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/dds/generic_subscription.hpp"
#include "mcvio/dds/graph_monitor.hpp"
#include "mcvio/dds/node.hpp"
#include "mcvio/dds/shutdown_signal.hpp"
#include "mcvio/dds/topic_names.hpp"
#include "mcvio/interfaces/message_registry.hpp"
#include "mcvio/interfaces/type_names.hpp"
#include "mcvio/rosmsg/cdr_codec.hpp"
#include "mcvio/rosmsg/yaml_printer.hpp"

namespace mcvio::cli {
namespace {

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", s);
  return buf;
}

std::string knownTypes() {
  std::string s;
  for (const auto& d : interfaces::MessageRegistry::all()) s += "\n  " + std::string(d.name);
  return s;
}

}  // namespace

void addEchoCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    std::string topic;
    std::string type;
    int count = 0;
    double timeout_s = 10.0;
    bool full_arrays = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("echo",
                                 "Print messages of a topic as YAML, like `ros2 topic echo`.\n"
                                 "The type is discovered from the topic's publishers unless --type is given.\n"
                                 "Examples:\n  mcvio echo /imu0 --count 1\n"
                                 "  mcvio echo /mcvio/odometry --type nav_msgs/msg/Odometry");
  cmd->add_option("topic", opt->topic, "ROS 2 topic name, e.g. /imu0")->required();
  cmd->add_option("--type", opt->type, "ROS 2 type, e.g. sensor_msgs/msg/Imu (default: discovered)");
  cmd->add_option("-n,--count", opt->count, "exit after this many messages (0 = until Ctrl-C)")
      ->check(finiteAtLeastZero())
      ->capture_default_str();
  cmd->add_option("--timeout", opt->timeout_s,
                  "seconds to wait for a publisher of the topic (and, with --count, for the messages)")
      ->check(finiteAtLeastZero(false))
      ->check(CLI::Range(0.0, 86400.0))
      ->capture_default_str();
  cmd->add_flag("--full-arrays", opt->full_arrays, "print every array element (default: the first 128)");
  cmd->callback([opt, &ctx] {
    dds::validateTopicName(opt->topic);
    const std::string topic = opt->topic.front() == '/' ? opt->topic : "/" + opt->topic;
    if (!opt->type.empty() && !interfaces::MessageRegistry::find(opt->type)) {
      throw CommandExit{2, "unknown type '" + opt->type + "' for " + topic + "; mcvio can decode:" + knownTypes()};
    }
    dds::GraphMonitor monitor;
    auto participant = dds::Participant::create(ctx.participantOptions("mcvio_echo"), &monitor);
    auto node = participant->createNode("_mcvio_echo_" + std::to_string(getpid()));
    const auto timeout = std::chrono::milliseconds(static_cast<int>(opt->timeout_s * 1000));
    dds::DiscoveredTopic found;
    const bool discovered = monitor.waitFor([&](const std::vector<dds::DiscoveredTopic>& topics) {
      for (const auto& t : topics) {
        if (t.name == topic && t.publishers > 0) {
          found = t;
          return true;
        }
      }
      return false;
    }, timeout);
    std::string type = opt->type;
    if (type.empty()) {
      if (!discovered) throw CommandExit{1, "no publisher of " + topic + " appeared within " +
                                              seconds(opt->timeout_s) + " (domain " +
                                              std::to_string(ctx.domain_id) + "); see `mcvio topics`"};
      type = found.type;
    } else if (discovered && found.type != type) {
      throw CommandExit{2, topic + " carries " + found.type + ", not " + type};
    }
    const auto* desc = interfaces::MessageRegistry::find(type);
    if (!desc) {
      throw CommandExit{2, "cannot decode " + topic + ": type '" + type + "' is not one mcvio knows; it can decode:" +
                               knownTypes()};
    }
    const auto defs = rosmsg::MessageDefinitionSet::parse(desc->name, desc->full_definition);
    rosmsg::CdrCodec codec(defs);
    rosmsg::YamlPrintOptions print;
    if (opt->full_arrays) print.max_array_elements = 0;
    std::mutex out_mutex;
    std::atomic<int> printed{0};
    dds::GenericSubscription sub(*node, topic, interfaces::rosToDdsTypeName(type), std::string(desc->type_hash),
                                 discovered ? found.compatibleReaderQos() : dds::QosProfile::defaults(),
                                 [&](const dds::ReceivedPayload& p) {
                                   std::lock_guard<std::mutex> lock(out_mutex);
                                   if (opt->count > 0 && printed.load() >= opt->count) return;
                                   try {
                                     std::cout << rosmsg::toYaml(codec.decode(*p.payload), print) << "---\n";
                                   } catch (const InputError& e) {
                                     std::cerr << "mcvio echo: " << topic << ": undecodable sample skipped: "
                                               << e.what() << "\n";
                                   }
                                   std::cout.flush();
                                   ++printed;
                                 });
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!dds::ShutdownSignal::requested()) {
      if (opt->count > 0 && printed.load() >= opt->count) return;
      if (opt->count > 0 && std::chrono::steady_clock::now() > deadline) {
        throw CommandExit{1, "received " + std::to_string(printed.load()) + " of " + std::to_string(opt->count) +
                                 " messages on " + topic + " within " + seconds(opt->timeout_s)};
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
}

}  // namespace mcvio::cli
