#pragma once
#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "mcvio/dds/node.hpp"
#include "mcvio/frontend/feature_tracker.hpp"
#include "mcvio/pipeline/vio_pipeline.hpp"

namespace mcvio::components {

/// Settings of the frontend component (the tracker's own options are inside).
struct FrontendComponentOptions {
  /// Default: the shipped configuration, as `mcvio run` without --config.
  frontend::FrontendOptions tracker = pipeline::VioPipelineOptions::shipped().frontend;
  /// Stereo calibration (EuRoC sensor.yaml folder). camera_info carries intrinsics but not the
  /// stereo extrinsics, so without this the component reports "no calibration" and skips frames.
  std::string calibration_dir;
  bool publish_tracks_image = false;  ///< /mcvio/tracks_image (rgb8) for RViz / Foxglove
  bool lossless = false;              ///< reliable keep-all inputs and outputs (offline pipelines)
  /// Left and right images within this much are one stereo pair [ns].
  Timestamp stereo_tolerance_ns = 1000000;
  /// Non-lossless: at most this many pairs wait for the tracker; older ones are dropped (logged).
  std::size_t max_queued_pairs = 4;
  /// "raw": sensor_msgs/Image on /cam0/image_raw, /cam1/image_raw; "compressed":
  /// sensor_msgs/CompressedImage (jpeg, png) on those names + "/compressed", as ROS 2's
  /// image_transport names them (remapping applies to the base names).
  std::string image_transport = "raw";

  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

struct FrontendComponentStats {
  std::size_t pairs_received = 0, frames_published = 0, frames_skipped = 0, pairs_dropped = 0;
  std::size_t unpaired_images = 0, bad_images = 0;
};

/// The frontend component: subscribes /cam0/image_raw, /cam1/image_raw (or their /compressed
/// streams) and /imu0, pairs the
/// images by stamp, tracks them with frontend::FeatureTracker on its own thread and publishes
/// /mcvio/features (mcvio_msgs/FeatureFrame) and, when asked, /mcvio/tracks_image.
/// Bad frames (wrong size or encoding, missing right image, out of order, no calibration) are
/// logged and skipped; the component keeps running.
class FrontendComponent {
 public:
  FrontendComponent(std::shared_ptr<dds::Node> node, FrontendComponentOptions options);
  ~FrontendComponent();
  FrontendComponentStats stats() const;
  /// The left and right image topics it reads, remapped (and with "/compressed" when asked).
  std::vector<std::string> imageTopics() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mcvio::components
