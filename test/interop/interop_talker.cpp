// interop_talker: publishes one deterministic message on each interop topic through mcvio_dds,
// as the ROS 2 node "interop_talker", every ~100 ms until SIGTERM/SIGINT, and subscribes to
// /interop/command (std_msgs/String) so the node has a reader on the graph too. Before
// publishing it writes the exact messages (and its participant's GID) to a JSON file that the
// independent Node.js peer (peer.js) compares field by field with what it decodes off the wire.
//
//   interop_talker --domain <0..232> --out <expected.json> [--period-ms <ms>]

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "interop_messages.hpp"
#include "std_msgs/msg/String.h"
#include "mcvio/dds/node.hpp"
#include "mcvio/dds/participant.hpp"
#include "mcvio/dds/qos_profile.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;

void onSignal(int) { g_stop = 1; }

struct Options {
  int domain_id = -1;
  std::string out_path;
  int period_ms = 100;
};

[[noreturn]] void usage(const std::string& problem) {
  std::cerr << "interop_talker: " << problem << "\n"
            << "usage: interop_talker --domain <0..232> --out <expected.json> [--period-ms <ms>]\n";
  std::exit(2);
}

int parseInt(const std::string& flag, const std::string& text) {
  try {
    std::size_t used = 0;
    const int value = std::stoi(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  usage(flag + " needs an integer, got \"" + text + "\"");
}

Options parseArgs(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) usage(arg + " needs a value");
    const std::string value = argv[++i];
    if (arg == "--domain") {
      o.domain_id = parseInt(arg, value);
    } else if (arg == "--out") {
      o.out_path = value;
    } else if (arg == "--period-ms") {
      o.period_ms = parseInt(arg, value);
    } else {
      usage("unknown argument " + arg);
    }
  }
  if (o.domain_id < 0 || o.domain_id > 232) usage("--domain must be in 0..232");
  if (o.out_path.empty()) usage("--out is required");
  if (o.period_ms <= 0) usage("--period-ms must be positive");
  return o;
}

// Written next to the target and renamed, so a reader never sees half a file.
void writeAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out.good()) throw std::runtime_error("cannot write " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot rename " + tmp + " to " + path);
}

std::string hex(const std::vector<std::uint8_t>& bytes) {
  static const char* kDigits = "0123456789abcdef";
  std::string out;
  for (const std::uint8_t b : bytes) {
    out += kDigits[b >> 4];
    out += kDigits[b & 0xf];
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseArgs(argc, argv);
  std::signal(SIGTERM, onSignal);
  std::signal(SIGINT, onSignal);

  const std::string kNodeName = "interop_talker";
  const std::string kNamespace = "/";
  const auto messages = mcvio::interop::InteropMessages::make();
  try {
    mcvio::dds::ParticipantOptions participant_options = mcvio::dds::ParticipantOptions::fromEnvironment();
    participant_options.domain_id = options.domain_id;
    participant_options.name = kNodeName;
    const auto participant = mcvio::dds::Participant::create(participant_options);
    const auto node = participant->createNode(kNodeName, kNamespace);
    writeAtomically(options.out_path, messages.toJson(kNamespace, kNodeName, hex(participant->gid())));

    using mcvio::dds::QosProfile;
    auto image = node->createPublisher<sensor_msgs::msg::dds_::Image_>("/interop/image", QosProfile::sensorData());
    auto imu = node->createPublisher<sensor_msgs::msg::dds_::Imu_>("/interop/imu", QosProfile::sensorData());
    auto camera_info = node->createPublisher<sensor_msgs::msg::dds_::CameraInfo_>(
        "/interop/camera_info", QosProfile::transientLocal(1));
    auto odometry = node->createPublisher<nav_msgs::msg::dds_::Odometry_>("/interop/odometry", QosProfile::defaults());
    auto tf = node->createPublisher<tf2_msgs::msg::dds_::TFMessage_>("/tf", QosProfile::defaults());
    std::atomic<long> commands{0};
    auto command = node->createSubscription<std_msgs::msg::dds_::String_>(
        mcvio::interop::kCommandTopic, QosProfile::defaults(), [&commands](const std_msgs::msg::dds_::String_& msg) {
          std::cout << "interop_talker: command \"" << msg.data() << "\"" << std::endl;
          ++commands;
        });

    std::cout << "interop_talker: domain " << options.domain_id << ", node " << node->fullName()
              << ", publishing every " << options.period_ms << " ms" << std::endl;
    long rounds = 0;
    while (g_stop == 0) {
      // Keep-last writers never block; a false here is a DDS error worth seeing in the log.
      const bool sent = image->publish(messages.image) && imu->publish(messages.imu) &&
                        camera_info->publish(messages.camera_info) && odometry->publish(messages.odometry) &&
                        tf->publish(messages.tf);
      if (!sent) std::cerr << "interop_talker: a publish failed in round " << rounds << "\n";
      if (++rounds % 50 == 0) {
        std::cout << "interop_talker: " << rounds << " rounds, matched readers image=" << image->matchedReaders()
                  << " imu=" << imu->matchedReaders() << " camera_info=" << camera_info->matchedReaders()
                  << " odometry=" << odometry->matchedReaders() << " tf=" << tf->matchedReaders() << std::endl;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(options.period_ms));
    }
    std::cout << "interop_talker: stopping after " << rounds << " rounds, " << commands << " commands received"
              << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "interop_talker: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
