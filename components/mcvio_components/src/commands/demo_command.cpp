// `mcvio demo`: the whole system on two simulated motion conflicts (DemoPipeline), reference
// against MC-VIO. `mcvio bus-demo`: a short, self-contained run on the bus, so a new user sees
// mcvio's topics flow and decode without any dataset. A "device" node publishes camera, IMU and
// calibration messages; a second participant, as any ROS 2 tool would, discovers them, decodes
// them and reports.
#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>
#include <unistd.h>

#include "commands/command_context.hpp"
#include "commands/demo_pipeline.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/dds/generic_subscription.hpp"
#include "mcvio/dds/graph_monitor.hpp"
#include "mcvio/dds/node.hpp"
#include "mcvio/dds/shutdown_signal.hpp"
#include "mcvio/interfaces/message_registry.hpp"
#include "mcvio/rosmsg/cdr_codec.hpp"
#include "mcvio/rosmsg/yaml_printer.hpp"

namespace mcvio::cli {
namespace {

using Image = sensor_msgs::msg::dds_::Image_;
using Imu = sensor_msgs::msg::dds_::Imu_;
using CameraInfo = sensor_msgs::msg::dds_::CameraInfo_;

void stamp(std_msgs::msg::dds_::Header_& h, std::int64_t t_ns, const char* frame) {
  h.stamp().sec(static_cast<std::int32_t>(t_ns / 1000000000));
  h.stamp().nanosec(static_cast<std::uint32_t>(t_ns % 1000000000));
  h.frame_id(frame);
}

// A checkerboard that slides one pixel per frame: enough texture to see motion in a viewer.
Image checkerboard(std::int64_t t_ns, int frame) {
  Image img;
  stamp(img.header(), t_ns, "cam0");
  img.height(480);
  img.width(752);
  img.encoding("mono8");
  img.step(752);
  img.data().resize(752 * 480);
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 752; ++u) {
      img.data()[v * 752 + u] = (((u + frame) / 32 + v / 32) % 2) ? 200 : 40;
    }
  }
  return img;
}

// IMU of a device swaying sideways at 0.5 Hz and resting otherwise: gravity plus the sway.
Imu imuSample(std::int64_t t_ns) {
  const double t = t_ns * 1e-9, w = 2 * M_PI * 0.5;
  Imu m;
  stamp(m.header(), t_ns, "imu0");
  m.orientation_covariance()[0] = -1;  // no orientation estimate, as REP-145 says
  m.angular_velocity().z(0.2 * w * std::cos(w * t));
  m.linear_acceleration().x(-0.3 * w * w * std::sin(w * t));
  m.linear_acceleration().z(9.81);
  for (int i = 0; i < 3; ++i) {
    m.angular_velocity_covariance()[i * 4] = 2.9e-8 * 200;
    m.linear_acceleration_covariance()[i * 4] = 4.0e-6 * 200;
  }
  return m;
}

CameraInfo cameraInfo(std::int64_t t_ns) {
  CameraInfo ci;
  stamp(ci.header(), t_ns, "cam0");
  ci.height(480);
  ci.width(752);
  ci.distortion_model("plumb_bob");
  // EuRoC cam0 intrinsics and radial-tangential distortion.
  ci.d({-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0.0});
  ci.k({458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1});
  ci.r({1, 0, 0, 0, 1, 0, 0, 0, 1});
  ci.p({458.654, 0, 367.215, 0, 0, 457.296, 248.375, 0, 0, 0, 1, 0});
  return ci;
}

void addPipelineDemoCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    DemoPipeline::Options pipeline;
    std::string only;
    bool quick = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "demo",
      "The whole system on two simulated motion conflicts, on this machine, in about a minute:\n"
      "  1. renders two stereo-inertial EuRoC sequences: an elevator ride (the cameras see a closed\n"
      "     cabin standing still while the IMU feels it move) and a self-occlusion (a carried laptop\n"
      "     covers most of the view), the conflict from 1/3 to 11/15 of the sequence;\n"
      "  2. for each, runs the Recorder (MCAP bag), the BackendComponent in MC-VIO mode, the\n"
      "     FrontendComponent and the Player (lossless, as fast as the readers allow) as DDS components,\n"
      "     and saves /mcvio/odometry and /mcvio/conflict as `mcvio run` would;\n"
      "  3. runs the same data offline in reference mode (no conflict handling);\n"
      "  4. evaluates both against ground truth and the conflict labels (`mcvio eval`) and prints\n"
      "     ATE, RPE, the reduction and the detector's TPR/FPR, with the paths of reports, plots, bags;\n"
      "     for the elevator also how high the ride went, how high each trajectory says, and how far\n"
      "     the cabin itself moved (MC-VIO's secondary frame, SEQ/mcvio/secondary.tum; the heights over\n"
      "     time in SEQ/report/ride_heights.png).\n"
      "Output per sequence SEQ in --out: SEQ/data (rendered), SEQ/bag, SEQ/mcvio, SEQ/reference,\n"
      "SEQ/report. Steps and the table go to stdout, the components' logs to stderr. It uses the DDS\n"
      "domain of --domain (default $ROS_DOMAIN_ID or 0) and refuses to start if the demo's topics are\n"
      "already published there; while it runs, other shells on that domain see them (`mcvio topics`).\n"
      "Examples:\n"
      "  mcvio demo\n"
      "  mcvio demo --quick --out /tmp/demo_quick          16 s sequences, 39 s measured here\n"
      "  mcvio demo --mode selective --duration 40 --keep  rerun later without rendering again");
  cmd->add_option("--out", opt->pipeline.out_dir, "output folder (created; the demo's own subfolders in it are replaced), "
                                                  "e.g. --out /tmp/my_demo")
      ->capture_default_str();
  cmd->add_option("--mode", opt->pipeline.mode,
                  "MC-VIO conflict handling of the DDS backend: imu (trust the IMU during a conflict), selective\n"
                  "(drop the landmarks that move with the conflicting frame) or auto (chooses per conflict), e.g. --mode imu")
      ->check(CLI::IsMember({"imu", "selective", "auto"}))
      ->capture_default_str();
  cmd->add_option("--duration", opt->pipeline.duration_s,
                  "length of each simulated sequence [s], 12..600; the whole demo takes about 2 s per simulated\n"
                  "second here (30 s: about a minute, 1 min 7 s measured), e.g. --duration 45")
      ->check(CLI::Range(12.0, 600.0))
      ->capture_default_str();
  cmd->add_flag("--quick", opt->quick, "16 s sequences (conflict 5.3-11.7 s) instead of --duration: a quicker look");
  cmd->add_flag("--keep", opt->pipeline.keep_images,
                "keep the rendered images (about 8 MB per simulated second) in --out; a later run with the same\n"
                "--duration then skips rendering. Without it they are removed at the end (ground truth, IMU and\n"
                "labels stay)");
  cmd->add_option("--only", opt->only, "run one sequence: elevator or self_occlusion, e.g. --only elevator")
      ->check(CLI::IsMember({"elevator", "self_occlusion"}));
  cmd->add_option("--seed", opt->pipeline.seed, "simulation seed (world, textures, noise), e.g. --seed 7")->capture_default_str();
  cmd->callback([opt, cmd, &ctx] {
    auto o = opt->pipeline;
    if (opt->quick) {
      if (cmd->count("--duration")) throw CommandExit{2, "--quick and --duration: choose one"};
      o.duration_s = 16.0;
    }
    if (!opt->only.empty()) o.scenarios = {opt->only};
    o.participant = ctx.participantOptions("mcvio_demo");
    const auto start = std::chrono::steady_clock::now();
    std::cout << "mcvio demo: " << (o.scenarios.size() > 1 ? "elevator and self_occlusion" : o.scenarios.front()) << ", " << o.duration_s << " s each, MC-VIO mode " << o.mode
              << ", output " << o.out_dir << "\n";
    std::vector<DemoPipeline::SequenceResult> results;
    try {
      results = DemoPipeline(o).run();
    } catch (const InputError&) {
      throw;
    } catch (const std::invalid_argument& e) {
      throw CommandExit{2, std::string("demo: ") + e.what()};
    } catch (const std::exception& e) {
      throw CommandExit{1, std::string("demo failed: ") + e.what()};
    }
    std::cout << DemoPipeline::summary(results, o.mode);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "\nmcvio demo: done in " << static_cast<int>(total + 0.5) << " s\n";
  });
}

void addBusDemoCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    double duration_s = 3.0;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "bus-demo",
      "Publish a short camera + IMU stream on the bus and echo it back through discovery, as a ROS 2\n"
      "tool on the same domain would see it. Shows the topics, types, one decoded message of each and\n"
      "the delivery counts. Example: mcvio bus-demo --duration 5");
  cmd->add_option("--duration", opt->duration_s, "seconds to publish (20 Hz images, 200 Hz IMU)")
      ->check(CLI::Range(0.5, 600.0))
      ->capture_default_str();
  cmd->callback([opt, &ctx] {
    std::cout << "mcvio bus-demo: domain " << ctx.domain_id << ", publishing for " << opt->duration_s << " s\n";
    // The device side.
    auto device_participant = dds::Participant::create(ctx.participantOptions("mcvio_demo_device"));
    auto device = device_participant->createNode("demo_device", "/mcvio");
    auto image_pub = device->createPublisher<Image>("/cam0/image_raw", dds::QosProfile::sensorData());
    auto imu_pub = device->createPublisher<Imu>("/imu0", dds::QosProfile::sensorData());
    auto info_pub = device->createPublisher<CameraInfo>("/cam0/camera_info", dds::QosProfile::transientLocal());

    // The observer side: discovers, subscribes generically and decodes with the .msg definitions.
    dds::GraphMonitor monitor;
    auto observer_participant = dds::Participant::create(ctx.participantOptions("mcvio_demo_observer"), &monitor);
    auto observer = observer_participant->createNode("_mcvio_demo_observer_" + std::to_string(getpid()));
    monitor.watchNodes(*observer);
    const std::vector<std::string> topics = {"/cam0/image_raw", "/imu0", "/cam0/camera_info"};
    if (!monitor.waitFor([&](const std::vector<dds::DiscoveredTopic>& found) {
          std::size_t n = 0;
          for (const auto& t : found) n += std::count(topics.begin(), topics.end(), t.name) && t.publishers > 0;
          return n == topics.size();
        }, std::chrono::seconds(10))) {
      throw CommandExit{1, "the demo's own topics were not discovered within 10 s: is multicast or shared "
                           "memory blocked? Try --dds-profiles config/dds/localhost_only.xml"};
    }
    struct Seen {
      std::string type, first_yaml;
      int count = 0;
    };
    std::mutex m;
    std::map<std::string, Seen> seen;
    std::vector<std::unique_ptr<dds::GenericSubscription>> subs;
    std::vector<std::unique_ptr<rosmsg::MessageDefinitionSet>> defs;
    std::vector<std::unique_ptr<rosmsg::CdrCodec>> codecs;
    for (const auto& t : monitor.topics()) {
      if (std::find(topics.begin(), topics.end(), t.name) == topics.end()) continue;
      const auto& desc = interfaces::MessageRegistry::get(t.type);
      defs.push_back(std::make_unique<rosmsg::MessageDefinitionSet>(
          rosmsg::MessageDefinitionSet::parse(desc.name, desc.full_definition)));
      codecs.push_back(std::make_unique<rosmsg::CdrCodec>(*defs.back()));
      auto* codec = codecs.back().get();
      const dds::QosProfile q = t.compatibleReaderQos();
      const std::string name = t.name, type = t.type;
      subs.push_back(std::make_unique<dds::GenericSubscription>(
          *observer, t.name, t.dds_type, t.type_hash, q, [&, name, type, codec](const dds::ReceivedPayload& p) {
            std::lock_guard<std::mutex> lock(m);
            auto& s = seen[name];
            s.type = type;
            if (s.count++ == 0) s.first_yaml = rosmsg::toYaml(codec->decode(*p.payload), rosmsg::YamlPrintOptions{6});
          }));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // let the readers match

    const auto start = std::chrono::steady_clock::now();
    const std::int64_t t0 = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                std::chrono::system_clock::now().time_since_epoch()).count();
    info_pub->publish(cameraInfo(t0));
    int images = 0, imus = 0;
    const int total_imu = static_cast<int>(opt->duration_s * 200);
    for (int k = 0; k < total_imu && !dds::ShutdownSignal::requested(); ++k) {
      const std::int64_t t = t0 + static_cast<std::int64_t>(k) * 5000000;
      imu_pub->publish(imuSample(t));
      ++imus;
      if (k % 10 == 0) {
        image_pub->publish(checkerboard(t, images));
        ++images;
      }
      std::this_thread::sleep_until(start + std::chrono::microseconds(5000 * (k + 1)));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto nodes = monitor.nodes();

    std::lock_guard<std::mutex> lock(m);
    std::cout << "\nTopics as a ROS 2 tool sees them (`ros2 topic list -t`):\n";
    for (const auto& t : topics) std::cout << "  " << t << " [" << seen[t].type << "]\n";
    std::cout << "\nNodes announced in ros_discovery_info (`ros2 node list`):\n";
    for (const auto& n : nodes) {
      if (n.name.front() != '_') std::cout << "  " << n.fullName() << "\n";
    }
    for (const auto& t : topics) {
      std::cout << "\nFirst message on " << t << " (decoded from its .msg definition):\n" << seen[t].first_yaml;
    }
    const int sent_info = 1;
    std::cout << "\nDelivered (best-effort sensor QoS may drop a few under load):\n";
    std::cout << "  /cam0/image_raw   " << seen["/cam0/image_raw"].count << " / " << images << "\n";
    std::cout << "  /imu0             " << seen["/imu0"].count << " / " << imus << "\n";
    std::cout << "  /cam0/camera_info " << seen["/cam0/camera_info"].count << " / " << sent_info << "\n";
    std::cout << "\nWhile it runs, on the same domain: `ros2 topic echo /imu0` or `mcvio echo /imu0` (another shell).\n";
    if (seen["/imu0"].count == 0 || seen["/cam0/image_raw"].count == 0 || seen["/cam0/camera_info"].count == 0) {
      throw CommandExit{1, "some topics delivered nothing"};
    }
  });
}

}  // namespace

void addDemoCommand(CLI::App& app, CommandContext& ctx) {
  addPipelineDemoCommand(app, ctx);
  addBusDemoCommand(app, ctx);
}

}  // namespace mcvio::cli
