#pragma once
#include <cstddef>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "mcvio/core/feature_frame.hpp"
#include "mcvio/core/topic_remapping.hpp"
#include "mcvio/pipeline/vio_pipeline.hpp"

namespace mcvio::pipeline {

struct OfflineRunOptions {
  /// EuRoC folder, or a rosbag2 bag with /cam0/image_raw, /cam1/image_raw and /imu0, or one with
  /// /mcvio/features (the frontend's output) and /imu0, which runs the estimator alone.
  std::string dataset_dir;
  /// Stereo calibration (EuRoC sensor.yaml folder); required for bags, which carry no extrinsics.
  std::string calibration_dir;
  std::string output_dir;   ///< trajectory.tum, stats.json
  std::string config_file;  ///< VioPipelineOptions YAML; empty = VioPipelineOptions::shipped()
  /// Conflict resolution mode (reference, imu, selective, auto); empty keeps the config's
  /// `estimator.conflict.mode`.
  std::string mode;
  bool progress = true;
  /// Image decoding, frontend and estimator on three threads, each a frame or more ahead of the
  /// next (the estimator sees the same input as with false, so the trajectory is the same);
  /// false: everything on the calling thread, one frame after the other.
  bool pipelined = true;
  /// Called with every frame's result, in frame order, from the thread that runs the estimator.
  std::function<void(std::size_t frame, const VioFrameResult& result)> on_frame;
  /// Polled before each frame is loaded; true ends the run with RunInterrupted, keeping what
  /// was written (stats.json then says "completed": false). `mcvio run` asks its Ctrl-C flag.
  std::function<bool()> stop_requested;
  /// Message definitions by ROS 2 type ("sensor_msgs/msg/Imu" -> .msg text with dependencies)
  /// for bag topics that carry none: rosbag2 sqlite3 files before Iron have no
  /// message_definitions table. `mcvio run` fills it with the built-in types.
  std::map<std::string, std::string> known_message_definitions;
  /// Bags: which of the bag's topics stand for /cam0/image_raw, /cam1/image_raw, /imu0 and
  /// /mcvio/features (`--remap /imu0:=/camera/imu`); a EuRoC folder takes none.
  TopicRemapping remapping;
};

/// Thrown by runOffline() when options.stop_requested said so.
struct RunInterrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct OfflineRunSummary {
  std::size_t frames = 0, estimated = 0, skipped = 0, resets = 0;
  double wall_seconds = 0, data_seconds = 0;
  double cpu_seconds = 0;       ///< user + system CPU of the process during the run
  double peak_rss_mb = 0;       ///< peak resident memory of the process so far (getrusage ru_maxrss)
  double frontend_median_cpu_ms = 0, backend_median_cpu_ms = 0, loader_median_cpu_ms = 0;  ///< per frame
  std::size_t not_initialized = 0;            ///< frames the estimator spent waiting to initialise
  std::size_t rejected = 0;                   ///< frames the initialised estimator turned down (no IMU yet, time order)
  std::string first_rejection;                ///< the estimator's reason for the first of them
  std::vector<std::string> skip_reasons;      ///< the first few distinct reasons frames were skipped
  double framesPerSecond() const { return wall_seconds > 0 ? static_cast<double>(frames) / wall_seconds : 0.0; }
  double realtimeFactor() const { return wall_seconds > 0 ? data_seconds / wall_seconds : 0.0; }
};

/// The input of an offline run: what runOffline() reads from a EuRoC folder or a bag, or what a
/// caller produces itself (a simulator rendering on the fly).
struct OfflineInput {
  StereoRigCalibration calibration;
  std::vector<ImuSample> imu;          ///< time order
  std::vector<Timestamp> frame_times;  ///< time order
  /// Left and right mono8 images of frame i. Called once per frame, in frame order, from one
  /// thread that may run a few frames ahead of the frontend.
  std::function<std::pair<cv::Mat, cv::Mat>(std::size_t)> images;
  /// Instead of images: the frontend's recorded output of frame i (a bag of /mcvio/features, as
  /// `mcvio demo` records what its backend got). The frontend is skipped and the estimator gets
  /// exactly what a DDS backend got. Called once per frame, in frame order.
  std::function<FeatureFrame(std::size_t)> features;
  std::vector<std::string> warnings;  ///< printed at the start of the run and kept in stats.json
  std::vector<std::string> notes;     ///< printed at the start of the run: which topics a bag is read from
};

/// `mcvio run`: the whole pipeline over a EuRoC folder or a recorded bag without DDS, deterministic.
/// A bag is read into memory first (images included): fine for minutes, not for hours. A bag
/// with /mcvio/features and /imu0 but no images runs the estimator alone on the recorded
/// features. Writes
/// OUT/trajectory.tum (t x y z qx qy qz qw per tracked frame, pose of imu0 in world, t in s),
/// OUT/conflict.csv (the motion-conflict statistics of every estimated frame), OUT/secondary.tum
/// (the conflicting frame S in the world while it is tracked) and OUT/stats.json (per-stage CPU
/// time, wall time, frames/s, real-time factor, peak memory, features, keyframes, statuses).
/// When a conflict window re-estimates earlier frames, trajectory.tum and secondary.tum hold the
/// final estimates and the per-frame output moves to trajectory_online.tum and
/// secondary_online.tum. Throws mcvio::InputError for bad input.
OfflineRunSummary runOffline(const OfflineRunOptions& options);

/// The same run over an input the caller holds; options.dataset_dir only names it in stats.json
/// and options.calibration_dir is not used.
OfflineRunSummary runOffline(const OfflineInput& input, const OfflineRunOptions& options);

/// Header line (with its newline) of OUT/conflict.csv; `mcvio demo` writes the same columns.
extern const char* const kConflictCsvHeader;

}  // namespace mcvio::pipeline
