#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dds/node.hpp"

namespace mcvio::components {

/// How the player replays a data set.
struct PlayerOptions {
  /// Speed relative to the recording: 1 = real time, 2 = twice as fast. Ignored when lossless.
  double rate = 1.0;
  /// Reliable keep-all QoS and no pacing: as fast as the slowest reader allows, nothing lost.
  bool lossless = false;
  /// Before publishing, wait this long for at least `min_readers` readers on every topic
  /// (lossless mode fails if they do not come: samples published before a reader matches are gone).
  double wait_for_readers_s = 10.0;
  int min_readers = 1;
  /// Readers to wait for on a topic on top of min_readers (`mcvio launch --processes`: the
  /// recorders in other processes that record it). Empty: none.
  std::function<int(const std::string& topic)> extra_readers;
  /// Then wait this long more: matching is two-sided, and a best-effort reader drops samples that
  /// arrive before it has matched the writer itself (the writer already counts it) [s].
  double settle_s = 0.5;
  bool loop = false;
  bool progress = true;
  /// Skip this much of the start and stop after this much (0 = all) [s].
  double start_s = 0.0;
  double duration_s = 0.0;
  /// A gap between consecutive messages longer than this (data time) is played as this long, with
  /// a warning: a far-future stamp in a damaged bag or a long pause in a recording would otherwise
  /// look like a hang. 10 s keeps the timing of any topic of 0.1 Hz or more. 0 = never shorten [s].
  double max_gap_s = 10.0;

  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

struct PlaybackSummary {
  std::size_t messages = 0;  ///< everything published
  std::size_t frames = 0, imu_samples = 0, ground_truth = 0;
  std::size_t skipped_frames = 0;  ///< images that could not be loaded (logged)
  std::size_t shortened_gaps = 0;  ///< gaps longer than max_gap_s (logged)
  double skipped_gap_seconds = 0;  ///< data time not waited for because of them
  double wall_seconds = 0, data_seconds = 0;
  bool interrupted = false;
};

/// The player component: publishes a EuRoC data set on the bus as a camera driver and IMU would.
///   /cam0/image_raw, /cam1/image_raw   sensor_msgs/Image mono8 (frames cam0, cam1)
///   /cam0/camera_info, /cam1/camera_info  with every frame (plumb_bob or equidistant)
///   /imu0                               sensor_msgs/Imu (frame imu0), 200 Hz
///   /ground_truth/odometry              nav_msgs/Odometry world -> imu0, when ground truth exists
/// Headers carry the data set's own timestamps.
class Player {
 public:
  Player(std::shared_ptr<dds::Node> node, const dataset::EurocDataset& data, PlayerOptions options);
  ~Player();
  /// Plays once (or until interrupted; loops when asked). Throws std::runtime_error when
  /// lossless readers do not appear or a lossless reader stops acknowledging.
  PlaybackSummary run();

 private:
  struct Publishers;
  std::shared_ptr<dds::Node> node_;
  const dataset::EurocDataset& data_;
  PlayerOptions options_;
  std::unique_ptr<Publishers> pubs_;
};

}  // namespace mcvio::components
