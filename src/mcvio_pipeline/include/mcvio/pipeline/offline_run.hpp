#pragma once
#include <string>

#include "mcvio/pipeline/vio_pipeline.hpp"

namespace mcvio::pipeline {

struct OfflineRunOptions {
  std::string dataset_dir;  ///< EuRoC folder, or a rosbag2 bag with /cam0/image_raw, /cam1/image_raw, /imu0
  /// Stereo calibration (EuRoC sensor.yaml folder); required for bags, which carry no extrinsics.
  std::string calibration_dir;
  std::string output_dir;   ///< trajectory.tum, stats.json
  std::string config_file;  ///< VioPipelineOptions YAML; empty = defaults
  bool progress = true;
};

struct OfflineRunSummary {
  std::size_t frames = 0, estimated = 0, skipped = 0, resets = 0;
  double wall_seconds = 0, data_seconds = 0;
};

/// `mcvio run`: the whole pipeline over a EuRoC folder or a recorded bag without DDS, deterministic.
/// A bag is read into memory first (images included): fine for minutes, not for hours. Writes
/// OUT/trajectory.tum (t x y z qx qy qz qw per tracked frame, pose of imu0 in world, t in s) and
/// OUT/stats.json (per-stage timing, features, keyframes, statuses). Throws mcvio::InputError for
/// bad input.
OfflineRunSummary runOffline(const OfflineRunOptions& options);

}  // namespace mcvio::pipeline
