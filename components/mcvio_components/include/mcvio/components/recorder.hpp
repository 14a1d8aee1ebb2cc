#pragma once
#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "mcvio/bag/bag_writer.hpp"
#include "mcvio/dds/generic_subscription.hpp"
#include "mcvio/dds/graph_monitor.hpp"
#include "mcvio/dds/node.hpp"

namespace mcvio::components {

/// Which topics to record and how to store them.
struct RecorderOptions {
  std::vector<std::string> topics;  ///< exact ROS 2 names ("/imu0")
  bool all = false;                 ///< every ROS 2 topic that appears
  std::string regex;                ///< ECMAScript regex on the ROS 2 name
  bag::BagWriterOptions bag;
  /// How often the recorder looks for new topics on the bus [s].
  double discovery_period_s = 0.1;

  /// Throws std::invalid_argument naming the problem (nothing selected, bad regex).
  void validate() const;
  /// Whether a topic of this ROS 2 name would be recorded (options validated).
  bool selects(const std::string& topic) const;
};

struct RecordingSummary {
  std::map<std::string, std::size_t> messages_per_topic;
  std::size_t messages = 0;
  std::uint64_t bytes = 0;
};

/// The recorder component: subscribes to the selected topics as they are discovered (any type,
/// through the raw-payload subscription, so topics of other ROS 2 nodes are recorded too) and
/// writes their CDR payloads to a rosbag2 bag: log time = receive time, publish time = the
/// message's header stamp (the writer's source timestamp for types without a header).
///
/// Samples are queued by the DDS threads and written by one writer thread, so a slow disk or a
/// compression burst never blocks reception. A reliable topic is read with a keep-all reader:
/// when the queue is the bottleneck, reliable publishers are slowed down, not dropped.
class Recorder {
 public:
  /// `participant` must have been created with `monitor` as its listener and hold no typed
  /// registrations of the recorded types (use a participant of its own).
  Recorder(std::shared_ptr<dds::Node> node, dds::GraphMonitor& monitor, const std::string& bag_dir,
           RecorderOptions options);
  ~Recorder();

  /// Starts watching the bus and recording. Returns immediately.
  void start();
  /// Stops subscribing, writes what is queued, closes the bag (metadata.yaml, MCAP summary).
  RecordingSummary stop();
  /// Topics subscribed so far.
  std::vector<std::string> recordedTopics() const;
  std::size_t messagesWritten() const { return written_.load(); }

 private:
  struct Queued {
    std::size_t topic_index;
    std::int64_t log_time, publish_time;
    std::vector<std::uint8_t> data;
  };
  bool selected(const dds::DiscoveredTopic& t) const;
  void discoveryLoop();
  void writerLoop();
  void subscribe(const dds::DiscoveredTopic& t);

  std::shared_ptr<dds::Node> node_;
  dds::GraphMonitor& monitor_;
  RecorderOptions options_;
  std::regex regex_;
  std::mutex writer_mutex_;  // BagWriter is single-threaded: discovery adds topics, the writer writes
  std::unique_ptr<bag::BagWriter> writer_;
  std::map<std::size_t, std::string> topic_names_;
  mutable std::mutex subs_mutex_;
  std::map<std::string, std::unique_ptr<dds::GenericSubscription>> subs_;
  std::mutex queue_mutex_;
  std::condition_variable queue_cv_;
  std::deque<Queued> queue_;
  std::atomic<bool> running_{false};
  std::atomic<std::size_t> written_{0};
  RecordingSummary summary_;
  std::thread discovery_thread_, writer_thread_;
};

}  // namespace mcvio::components
