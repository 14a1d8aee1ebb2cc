#include <chrono>
#include <iostream>
#include <thread>
#include <unistd.h>

#include "commands/command_context.hpp"
#include "mcvio/bag/bag_info.hpp"
#include "mcvio/bag/bag_reindexer.hpp"
#include "mcvio/bag/compression.hpp"
#include "mcvio/components/recorder.hpp"
#include "mcvio/dds/shutdown_signal.hpp"
#include "mcvio/dds/topic_names.hpp"

namespace mcvio::cli {

void addRecordCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    std::string out, storage = "mcap", compression = "zstd";
    std::vector<std::string> topics;
    bool all = false;
    std::string regex;
    std::uint64_t max_size = 0;
    double max_duration = 0, duration = 0;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "record",
      "Record topics to a rosbag2 bag (metadata.yaml + MCAP or sqlite3), like `ros2 bag record`.\n"
      "Types are discovered on the bus, so topics of any ROS 2 node are recorded; payloads are kept\n"
      "byte for byte. Ctrl-C closes the bag; after a kill -9, `mcvio bag reindex` recovers it.\n"
      "Examples:\n"
      "  mcvio record -o /tmp/run --all\n"
      "  mcvio record -o /tmp/imu /imu0 /cam0/camera_info --storage sqlite3\n"
      "  mcvio record -o /tmp/cams --regex '^/cam[01]/' --compression lz4 --max-bag-size 500000000");
  cmd->add_option("-o,--output", opt->out, "bag directory to create")->required();
  cmd->add_option("topics", opt->topics, "topics to record");
  cmd->add_flag("-a,--all", opt->all, "record every ROS 2 topic that appears");
  cmd->add_option("-e,--regex", opt->regex, "record topics whose name matches this regular expression");
  cmd->add_option("-s,--storage", opt->storage, "mcap or sqlite3")->check(CLI::IsMember({"mcap", "sqlite3"}))->capture_default_str();
  cmd->add_option("--compression", opt->compression, "zstd, lz4 or none")->check(CLI::IsMember({"zstd", "lz4", "none"}))->capture_default_str();
  cmd->add_option("--max-bag-size", opt->max_size, "split into a new file after this many bytes (0 = never)")
      ->check(finiteAtLeastZero());
  cmd->add_option("--max-bag-duration", opt->max_duration, "split into a new file after this many seconds (0 = never)")
      ->check(finiteAtLeastZero());
  cmd->add_option("--duration", opt->duration, "stop after this many seconds (0 = until Ctrl-C)")
      ->check(finiteAtLeastZero());
  cmd->callback([opt, &ctx] {
    if (opt->out.empty()) throw CommandExit{2, "record: -o/--output is empty; name the bag directory to create"};
    // Before joining the bus: a misspelt name would otherwise record nothing without a word.
    for (const auto& t : opt->topics) dds::validateTopicName(t);
    components::RecorderOptions ro;
    ro.topics = opt->topics;
    ro.all = opt->all;
    ro.regex = opt->regex;
    ro.bag.storage = opt->storage;
    ro.bag.compression = opt->compression == "zstd" ? bag::Compression::Zstd
                         : opt->compression == "lz4" ? bag::Compression::Lz4 : bag::Compression::None;
    ro.bag.max_bagfile_size = opt->max_size;
    ro.bag.max_bagfile_duration = fromSeconds(opt->max_duration);
    ro.validate();
    dds::GraphMonitor monitor;
    auto participant = dds::Participant::create(ctx.participantOptions("mcvio_recorder"), &monitor);
    auto node = participant->createNode("recorder", "/mcvio");
    components::Recorder recorder(node, monitor, opt->out, ro);
    recorder.start();
    std::cerr << "mcvio record: writing " << opt->out << " (" << opt->storage << ", " << opt->compression
              << "); Ctrl-C to stop\n";
    const auto start = std::chrono::steady_clock::now();
    while (!dds::ShutdownSignal::requested()) {
      if (opt->duration > 0 && std::chrono::steady_clock::now() - start > std::chrono::duration<double>(opt->duration)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    const auto s = recorder.stop();
    std::cerr << "mcvio record: " << s.messages << " messages, " << s.bytes << " bytes\n";
    for (const auto& [topic, n] : s.messages_per_topic) std::cerr << "  " << topic << ": " << n << "\n";
  });
}

void addBagCommand(CLI::App& app, CommandContext&) {
  auto* cmd = app.add_subcommand("bag", "Inspect and repair rosbag2 bags.\n"
                                        "Examples:\n  mcvio bag info /tmp/run\n  mcvio bag info --verify /tmp/run\n  mcvio bag reindex /tmp/run");
  cmd->require_subcommand(1);
  auto path = std::make_shared<std::string>();
  auto verify = std::make_shared<bool>(false);
  auto* info = cmd->add_subcommand(
      "info",
      "Files, duration, message counts and topics of a bag, like `ros2 bag info`.\n"
      "Each storage file is opened and checked against metadata.yaml (MCAP: its summary; sqlite3:\n"
      "its statistics and first message): fast, but most messages are not read. --verify also\n"
      "reads and decompresses every message (every MCAP chunk with its CRC, every sqlite3 row),\n"
      "as long as reading the whole bag takes, without changing it, and reports per topic how many\n"
      "messages are unreadable and where the first one is (file, row id or byte offset, log time).\n"
      "Problems are WARNING lines (naming `mcvio bag reindex` only where it repairs them) and exit\n"
      "status 1.\n"
      "Examples:\n"
      "  mcvio bag info /tmp/run\n"
      "  mcvio bag info --verify /tmp/run     before a long `mcvio run` on a copied or old bag");
  info->add_option("bag", *path, "bag directory (or a single .mcap / .db3 file, described from its own summary)")->required();
  info->add_flag("--verify", *verify,
                 "read and decompress every message of every storage file (slow on big bags)");
  info->callback([path, verify] {
    std::vector<std::string> warnings;
    bag::BagInfoOptions options;
    options.verify = *verify;
    const bool tty = isatty(STDERR_FILENO) != 0;
    if (*verify && tty) {
      options.progress = [](std::uint64_t n) {
        std::cerr << "\rmcvio bag info: " << n << " messages verified" << std::flush;
      };
    }
    const std::string text = bag::bagInfo(*path, &warnings, options);
    if (options.progress) std::cerr << "\r\033[K" << std::flush;  // clear the progress line
    std::cout << text;
    for (const auto& w : warnings) std::cerr << "mcvio bag info: WARNING: " << w << "\n";
    if (!warnings.empty()) {
      throw CommandExit{1, *verify ? "bag info: unreadable messages, or metadata.yaml and the storage files disagree (see WARNING lines)"
                                   : "bag info: metadata.yaml and the storage files disagree or a file is unreadable (see WARNING lines)"};
    }
  });
  auto* reindex = cmd->add_subcommand(
      "reindex",
      "Rebuild metadata.yaml and the MCAP summary/indexes of a bag whose recorder was killed or whose\n"
      "files are damaged. Every chunk is checked (CRC, records, indexes); every intact chunk is kept,\n"
      "also those after a damaged one. Damaged records and a killed writer's unfinished last record\n"
      "are dropped and reported (byte offset, size, messages lost if known). A file with damage inside\n"
      "is rewritten beside it and the untouched original kept as <file>.orig; a killed writer's file is\n"
      "finished in place (its unfinished last record cannot be read anyway). sqlite3: write-ahead\n"
      "logs are folded in (every committed transaction is kept). A file that cannot be read at all\n"
      "(not MCAP, a damaged database) is left in place and out of metadata.yaml; the others are indexed.\n"
      "Exit status 1 when damaged data was dropped (the bag is readable again), 0 otherwise.");
  reindex->add_option("bag", *path, "bag directory")->required();
  reindex->callback([path] {
    std::vector<std::string> log;
    std::vector<std::string> damage;
    const auto meta = bag::BagReindexer::reindex(*path, &log, &damage);
    for (const auto& l : log) std::cerr << "mcvio bag reindex: " << l << "\n";
    for (const auto& d : damage) std::cerr << "mcvio bag reindex: WARNING: " << d << "\n";
    std::cout << bag::bagInfo(*path);
    if (!damage.empty()) {
      throw CommandExit{1, "bag reindex: " + std::to_string(damage.size()) +
                               " damaged stretch(es) or unreadable file(s) dropped, see the WARNING lines; nothing was "
                               "deleted (repaired files keep their originals as *.orig)"};
    }
  });
}

}  // namespace mcvio::cli
