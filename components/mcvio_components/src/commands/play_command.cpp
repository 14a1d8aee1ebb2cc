#include <filesystem>
#include <iostream>

#include "commands/command_context.hpp"
#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/components/bag_player.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dds/node.hpp"

namespace mcvio::cli {

void addPlayCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    std::string dataset;
    std::vector<std::string> topics, remap;
    components::PlayerOptions player;
    bool quiet = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "play",
      "Publish a EuRoC data set on the bus as its sensors would: /cam0/image_raw, /cam1/image_raw,\n"
      "/cam0/camera_info, /cam1/camera_info, /imu0 and /ground_truth/odometry, stamped with the data\n"
      "set's own time.\n"
      "Examples:\n"
      "  mcvio play ../shared/data/euroc_V1_01_excerpt --rate 2\n"
      "  mcvio play /data/sim_elevator --lossless        # as fast as readers allow, nothing lost\n"
      "  mcvio play /tmp/run.bag --topics /imu0 --rate 0.5  # a recorded bag, original timing\n"
      "  mcvio play /tmp/run.bag --max-gap 1   # pauses over 1 s of data take 1 s (0 keeps them)\n"
      "  mcvio play /tmp/driver.bag --remap /camera/imu:=/imu0   # publish a bag topic under another name");
  cmd->add_option("dataset", opt->dataset, "EuRoC folder (holding mav0/), or a rosbag2 bag (directory with metadata.yaml, .mcap, .db3)")->required();
  cmd->add_option("--topics", opt->topics, "bags only: play just these topics");
  cmd->add_option("-r,--rate", opt->player.rate, "playback speed relative to real time")->capture_default_str();
  cmd->add_flag("--lossless", opt->player.lossless,
                "reliable keep-all QoS, no pacing: as fast as the slowest reader allows, nothing lost");
  cmd->add_flag("--loop", opt->player.loop, "start again at the end");
  cmd->add_option("--start", opt->player.start_s, "skip this many seconds of the start")->capture_default_str();
  cmd->add_option("--duration", opt->player.duration_s, "play this many seconds (0 = all)")->capture_default_str();
  cmd->add_option("--max-gap", opt->player.max_gap_s,
                  "seconds of data: a longer pause between consecutive messages (a far-future stamp in a\n"
                  "damaged bag, a paused recording) is played as this long, with a warning naming the topic,\n"
                  "instead of being slept through (0 = keep every gap)")
      ->capture_default_str();
  cmd->add_option("--wait-for-readers", opt->player.wait_for_readers_s,
                  "seconds to wait for a reader on every topic before starting (lossless fails without)")
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", opt->quiet, "no progress bar");
  addRemapOption(cmd, opt->remap, "/imu0:=/camera/imu (a bag: FROM is the bag's topic)");
  cmd->callback([opt, &ctx] {
    const auto remapping = TopicRemapping::parse(opt->remap);
    namespace fs = std::filesystem;
    const auto gaps = [](const components::PlaybackSummary& s) {
      return s.shortened_gaps ? ", " + std::to_string(s.shortened_gaps) + " long gaps shortened by " +
                                    std::to_string(s.skipped_gap_seconds) + " s (--max-gap)"
                              : std::string();
    };
    const fs::path p(opt->dataset);
    const bool is_bag = bag::BagReader::looksLikeBag(p);
    opt->player.progress = !opt->quiet;
    opt->player.validate();
    if (is_bag) {
      auto participant = dds::Participant::create(ctx.participantOptions("mcvio_player"));
      auto node = participant->createNode("player", "/mcvio", remapping);
      components::BagPlayer player(node, opt->dataset, opt->player, opt->topics);
      const auto s = player.run();
      std::cerr << "mcvio play: " << s.messages << " messages in " << s.wall_seconds << " s ("
                << s.data_seconds << " s of recording)" << gaps(s) << (s.interrupted ? ", interrupted" : "") << "\n";
      if (s.interrupted) throw CommandExit{130, ""};
      return;
    }
    if (!opt->topics.empty()) throw std::invalid_argument("play: --topics applies to bags, not EuRoC folders");
    const auto data = dataset::EurocDataset::open(opt->dataset);
    for (const auto& w : data.warnings()) std::cerr << "mcvio play: warning: " << w << "\n";
    auto participant = dds::Participant::create(ctx.participantOptions("mcvio_player"));
    auto node = participant->createNode("player", "/mcvio", remapping);
    components::Player player(node, data, opt->player);
    warnUnusedRemapRules(*node, "play");
    const auto s = player.run();
    std::cerr << "mcvio play: " << s.frames << " stereo frames, " << s.imu_samples << " IMU samples, " << s.ground_truth
              << " ground-truth poses in " << s.wall_seconds << " s (" << s.data_seconds << " s of data)"
              << (s.skipped_frames ? ", " + std::to_string(s.skipped_frames) + " frames skipped" : "") << gaps(s)
              << (s.interrupted ? ", interrupted" : "") << "\n";
    if (s.interrupted) throw CommandExit{130, ""};
  });
}

}  // namespace mcvio::cli
