#include "mcvio/components/launcher.hpp"

#include <chrono>
#include <functional>
#include <memory>
#include <sstream>
#include <thread>

#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/components/backend_component.hpp"
#include "mcvio/components/bag_player.hpp"
#include "mcvio/components/frontend_component.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/components/recorder.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dds/graph_monitor.hpp"
#include "mcvio/dds/node.hpp"
#include "mcvio/dds/shutdown_signal.hpp"

namespace mcvio::components {

namespace {

using Clock = std::chrono::steady_clock;
using Kind = LaunchPlan::Kind;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Waits until `state()` has not changed for `quiet` and `done()` holds, or `timeout` passes (or,
// with `until_signal`, Ctrl-C). True when it got there.
bool waitUntilSettled(const std::function<std::vector<std::size_t>()>& state, const std::function<bool()>& done,
                      std::chrono::milliseconds quiet, std::chrono::duration<double> timeout, bool until_signal = true) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(timeout);
  auto last = state();
  auto since = Clock::now();
  while (Clock::now() < deadline && !(until_signal && dds::ShutdownSignal::requested())) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const auto now = state();
    if (now != last) {
      last = now;
      since = Clock::now();
    } else if (Clock::now() - since >= quiet && done()) {
      return true;
    }
  }
  return false;
}

}  // namespace

Launcher::Launcher(LaunchPlan plan, dds::ParticipantOptions participant, std::ostream* log)
    : plan_(std::move(plan)), participant_(std::move(participant)), log_(log) {}

Launcher::Result Launcher::run(const Control& control) {
  const auto t0 = Clock::now();
  const auto say = [this](const std::string& line) {
    if (log_) *log_ << "mcvio launch: " << line << "\n" << std::flush;
  };
  // A remap rule that matched none of a component's topics does nothing: most likely a typo.
  const auto warnUnusedRules = [&say](const dds::Node& node, const std::string& name) {
    for (const auto& rule : node.unusedRemapRules())
      say("warning: component '" + name + "': remap " + rule + " matches none of its topics");
  };
  // One slot per entry; declared so that destruction runs components, then participants, then the
  // recorders' graph monitors (a participant's listener must outlive it).
  struct Slot {
    std::unique_ptr<dds::GraphMonitor> monitor;
    std::shared_ptr<dds::Participant> participant;
    std::unique_ptr<dataset::EurocDataset> data;
    std::unique_ptr<Recorder> recorder;
    std::unique_ptr<FrontendComponent> frontend;
    std::unique_ptr<BackendComponent> backend;
    std::unique_ptr<Player> player;
    std::unique_ptr<BagPlayer> bag_player;
    std::vector<std::unique_ptr<dds::ReaderEndpoint>> stand_ins;
    bool recording = false;
  };
  std::vector<Slot> slots(plan_.entries.size());
  Result result;
  result.entries.resize(plan_.entries.size());

  const auto stopRecorders = [&] {
    for (std::size_t i = 0; i < slots.size(); ++i) {
      if (!slots[i].recording) continue;
      result.entries[i].recording = slots[i].recorder->stop();
      slots[i].recording = false;
    }
  };
  const auto participantFor = [&](const LaunchPlan::Entry& e, dds::GraphMonitor* monitor) {
    auto o = participant_;
    o.name = "mcvio_" + e.name;
    return dds::Participant::create(o, monitor);
  };

  try {
    // Everything but the players, in the file's order; the players once the rest is listening.
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t i = 0; i < plan_.entries.size(); ++i) {
        const auto& e = plan_.entries[i];
        auto& s = slots[i];
        result.entries[i].name = e.name;
        result.entries[i].kind = e.kind;
        if ((e.kind == Kind::kPlayer) != (pass == 1)) continue;
        switch (e.kind) {
          case Kind::kRecorder:
            s.monitor = std::make_unique<dds::GraphMonitor>();
            s.participant = participantFor(e, s.monitor.get());
            s.recorder = std::make_unique<Recorder>(s.participant->createNode(e.name, e.node_namespace), *s.monitor,
                                                    e.output, e.recorder);
            s.recorder->start();
            s.recording = true;
            say("recorder '" + e.name + "' writing " + e.output + " (" + e.recorder.bag.storage + ")");
            break;
          case Kind::kFrontend: {
            s.participant = participantFor(e, nullptr);
            auto node = s.participant->createNode(e.name, e.node_namespace, e.remapping);
            s.frontend = std::make_unique<FrontendComponent>(node, e.frontend);
            const auto images = s.frontend->imageTopics();
            say("frontend '" + e.name + "' tracking " + images[0] + " + " + images[1] + " (calibration " +
                e.frontend.calibration_dir + ")");
            warnUnusedRules(*node, e.name);
            break;
          }
          case Kind::kBackend: {
            s.participant = participantFor(e, nullptr);
            auto node = s.participant->createNode(e.name, e.node_namespace, e.remapping);
            s.backend = std::make_unique<BackendComponent>(node, e.backend);
            warnUnusedRules(*node, e.name);
            say("backend '" + e.name + "' estimating, mode " +
                std::string(conflict::toString(e.backend.estimator.conflict.mode)) + " (calibration " +
                e.backend.calibration_dir + ")");
            break;
          }
          case Kind::kPlayer: {
            s.participant = participantFor(e, nullptr);
            auto node = s.participant->createNode(e.name, e.node_namespace, e.remapping);
            if (bag::BagReader::looksLikeBag(e.input)) {
              s.bag_player = std::make_unique<BagPlayer>(node, e.input, e.player, e.topics);
              say("player '" + e.name + "' playing the bag " + e.input);
              break;
            }
            if (!e.topics.empty())
              throw InputError(plan_.source + ": component '" + e.name + "': 'topics' applies to bags, and " + e.input +
                               " is a EuRoC folder");
            s.data = std::make_unique<dataset::EurocDataset>(dataset::EurocDataset::open(e.input));
            for (const auto& w : s.data->warnings()) say("warning: " + w);
            s.player = std::make_unique<Player>(node, *s.data, e.player);
            {
              // A player waits for a reader of every topic it plays (a lossless one fails without);
              // the components read the calibration folder, not camera_info, and only a recorder
              // may want the ground truth: without these it would wait wait_for_readers per topic.
              auto readers = s.participant->createNode(e.name + "_sinks", e.node_namespace, e.remapping);
              const auto q = dds::QosProfile::lossless();
              s.stand_ins.push_back(readers->createSubscription<sensor_msgs::msg::dds_::CameraInfo_>(
                  "/cam0/camera_info", q, [](const auto&) {}));
              s.stand_ins.push_back(readers->createSubscription<sensor_msgs::msg::dds_::CameraInfo_>(
                  "/cam1/camera_info", q, [](const auto&) {}));
              s.stand_ins.push_back(readers->createSubscription<nav_msgs::msg::dds_::Odometry_>(
                  "/ground_truth/odometry", q, [](const auto&) {}));
            }
            warnUnusedRules(*node, e.name);
            say("player '" + e.name + "' playing " + e.input + " (" + std::to_string(s.data->stereoFrames().size()) +
                " stereo frames" + (e.player.lossless ? ", lossless" : "") + ")");
            break;
          }
        }
      }
      // Before anything plays: let the recorders subscribe to what is on the bus (a topic found
      // later loses its first messages).
      if (pass == 1 && plan_.has(Kind::kRecorder) && plan_.has(Kind::kPlayer)) {
        waitUntilSettled(
            [&] {
              std::vector<std::size_t> n;
              for (const auto& s : slots)
                if (s.recorder) n.push_back(s.recorder->recordedTopics().size());
              return n;
            },
            [] { return true; }, std::chrono::milliseconds(500), std::chrono::seconds(10));
      }
    }

    if (control.started) control.started();

    // Play, each player on a thread of its own; then wait for the rest to catch up.
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < slots.size(); ++i) {
      auto& s = slots[i];
      if (!s.player && !s.bag_player) continue;
      threads.emplace_back([&s, &r = result.entries[i]] {
        try {
          r.playback = s.player ? s.player->run() : s.bag_player->run();
        } catch (const std::exception& ex) {
          r.error = ex.what();
        }
      });
    }
    for (auto& t : threads) t.join();
    bool player_failed = false;
    for (const auto& r : result.entries) {
      if (r.kind != Kind::kPlayer) continue;
      result.interrupted = result.interrupted || r.playback.interrupted;
      if (!r.error.empty()) {
        say("player '" + r.name + "' failed: " + r.error);
        player_failed = true;
      }
    }
    const bool played = !threads.empty() && !player_failed;
    const auto counters = [&] {
      std::vector<std::size_t> n;
      for (const auto& s : slots) {
        if (s.frontend) {
          const auto f = s.frontend->stats();
          n.insert(n.end(), {f.pairs_received, f.frames_published, f.frames_skipped, f.pairs_dropped});
        }
        if (s.backend) {
          const auto b = s.backend->stats();
          n.insert(n.end(), {b.frames_received, b.frames_processed, b.imu_received});
        }
        if (s.recorder) n.push_back(s.recorder->messagesWritten());
      }
      return n;
    };
    const auto handled = [&] {
      for (const auto& s : slots) {
        if (s.frontend) {
          const auto f = s.frontend->stats();
          if (f.frames_published + f.frames_skipped + f.pairs_dropped < f.pairs_received) return false;
        }
      }
      return true;
    };
    const auto drain = [&] {
      result.drained = waitUntilSettled(counters, handled, std::chrono::milliseconds(1000),
                                        std::chrono::duration<double>(plan_.drain_timeout_s));
      if (!result.drained && !dds::ShutdownSignal::requested())
        say("warning: the components had not caught up after drain_timeout (" + std::to_string(plan_.drain_timeout_s) +
            " s); stopping anyway");
    };
    if (played && !result.interrupted && plan_.exit_when_played) {
      say("playback done; waiting for the components to handle what it published");
      drain();
    } else if (!player_failed && !result.interrupted) {
      say(threads.empty() ? "running; Ctrl-C to stop" : "playback done; running until Ctrl-C (exit_when_played: false)");
      bool data_ended = false;
      while (!dds::ShutdownSignal::waitFor(std::chrono::milliseconds(100)))
        if (threads.empty() && control.data_ended && control.data_ended()) {
          data_ended = true;
          break;
        }
      if (data_ended) {
        say("the data has ended; handling what is queued");
        drain();
      }
    }
    result.interrupted = result.interrupted || dds::ShutdownSignal::requested();
    for (auto& s : slots)
      if (s.backend) s.backend->flush();  // frames still waiting for IMU that will not come now
    // What the flush published still has to reach the recorders, after a Ctrl-C too (bounded).
    if (plan_.has(Kind::kRecorder))
      waitUntilSettled(counters, [] { return true; }, std::chrono::milliseconds(500), std::chrono::seconds(5), false);
    for (std::size_t i = 0; i < slots.size(); ++i) {
      if (slots[i].frontend) result.entries[i].frontend = slots[i].frontend->stats();
      if (slots[i].backend) result.entries[i].backend = slots[i].backend->stats();
    }
    stopRecorders();
  } catch (...) {
    // A component that cannot start: close the bags already open, then report.
    try {
      stopRecorders();
    } catch (...) {
    }
    throw;
  }
  // Each slot ends its components, then its participant, then its monitor (member order).
  slots.clear();
  result.wall_seconds = secondsSince(t0);
  return result;
}

std::string Launcher::summary(const Result& result) {
  std::ostringstream os;
  for (const auto& r : result.entries) {
    os << "  " << LaunchPlan::kindName(r.kind) << " '" << r.name << "': ";
    switch (r.kind) {
      case Kind::kPlayer: {
        const auto& p = r.playback;
        if (!r.error.empty()) {
          os << "failed: " << r.error;
        } else {
          os << p.messages << " messages (" << p.frames << " stereo frames, " << p.imu_samples << " IMU samples) in "
             << p.wall_seconds << " s" << (p.skipped_frames ? ", " + std::to_string(p.skipped_frames) + " frames skipped" : "")
             << (p.interrupted ? ", interrupted" : "");
        }
        break;
      }
      case Kind::kFrontend: {
        const auto& f = r.frontend;
        os << f.pairs_received << " stereo pairs, " << f.frames_published << " feature frames published, "
           << f.frames_skipped << " skipped, " << f.pairs_dropped << " dropped, " << f.bad_images << " bad images";
        break;
      }
      case Kind::kBackend: {
        const auto& b = r.backend;
        os << b.frames_received << " feature frames (" << b.frames_rejected << " rejected, " << b.frames_dropped
           << " dropped, " << b.frames_not_accepted << " refused by the estimator), " << b.poses_published << " poses, "
           << b.not_initialized << " before initialisation, " << b.resets << " resets, " << b.conflict_frames
           << " in conflict; estimator CPU mean " << b.estimator_cpu_ms_mean << " ms";
        break;
      }
      case Kind::kRecorder:
        os << r.recording.messages << " messages on " << r.recording.messages_per_topic.size() << " topics, "
           << r.recording.bytes << " bytes";
        break;
    }
    os << "\n";
  }
  os << "  " << result.wall_seconds << " s" << (result.interrupted ? ", interrupted" : "")
     << (result.drained ? "" : ", stopped before the components caught up") << "\n";
  return os.str();
}

}  // namespace mcvio::components
