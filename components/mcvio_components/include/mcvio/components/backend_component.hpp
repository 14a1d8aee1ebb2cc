#pragma once
#include <cstddef>
#include <memory>
#include <string>

#include "mcvio/dds/node.hpp"
#include "mcvio/estimator/estimator_options.hpp"
#include "mcvio/pipeline/vio_pipeline.hpp"

namespace mcvio::components {

/// Settings of the backend component (the estimator's own options are inside).
struct BackendComponentOptions {
  /// Default: the shipped configuration, as `mcvio run` without --config.
  estimator::EstimatorOptions estimator = pipeline::VioPipelineOptions::shipped().estimator;
  /// Stereo-inertial calibration (EuRoC sensor.yaml folder): extrinsics, focal length and IMU noise
  /// for the estimator, and the imu0 -> cam0/cam1 transforms on /tf_static. Required.
  std::string calibration_dir;
  std::string world_frame = "world";
  std::string body_frame = "imu0";             ///< child of /mcvio/odometry and of the /tf transform
  std::string secondary_frame = "conflict_frame";  ///< child of /mcvio/secondary_odometry
  /// Reliable keep-all inputs and outputs, and no frame is ever dropped: offline pipelines, where
  /// the DDS run must give `mcvio run`'s trajectory.
  bool lossless = false;
  /// /mcvio/landmarks every this many estimated frames (0: never).
  std::size_t landmarks_every_n_frames = 1;
  /// /mcvio/path and /mcvio/secondary_path keep the newest this many poses (0: all; a long run makes every Path message
  /// large, 10000 poses are about 8 minutes at 20 Hz).
  std::size_t max_path_poses = 10000;
  /// Not lossless: a feature frame waits at most this long (wall clock) for IMU up to its stamp,
  /// then goes to the estimator with what there is (which rejects it if the IMU does not reach it) [s].
  double max_imu_wait_s = 0.5;
  /// Not lossless: at most this many feature frames wait; the oldest beyond are dropped (logged).
  std::size_t max_queued_frames = 10;

  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

struct BackendComponentStats {
  std::size_t imu_received = 0, imu_rejected = 0;        ///< rejected: non-finite or not after the previous
  std::size_t frames_received = 0, frames_rejected = 0;  ///< rejected on arrival: stamp not after the previous
  std::size_t frames_dropped = 0;      ///< not lossless: the queue was full
  std::size_t frames_processed = 0;    ///< given to the estimator
  std::size_t frames_not_accepted = 0; ///< the estimator refused them (message logged)
  std::size_t poses_published = 0;     ///< /mcvio/odometry messages
  std::size_t not_initialized = 0, resets = 0, conflict_frames = 0, secondary_published = 0;
  /// Wall time from a feature frame's arrival to its odometry being published [ms].
  double latency_ms_mean = 0, latency_ms_max = 0;
  /// Estimator CPU time per frame [ms].
  double estimator_cpu_ms_mean = 0, estimator_cpu_ms_max = 0;
};

/// The backend component: subscribes /imu0 (sensor_msgs/Imu) and /mcvio/features
/// (mcvio_msgs/FeatureFrame), runs estimator::SlidingWindowEstimator on its own thread, and
/// publishes
///   /mcvio/odometry            nav_msgs/Odometry world -> imu0 (pose covariance in world axes)
///   /mcvio/path                nav_msgs/Path (transient local)
///   /tf                        world -> imu0 per estimated frame
///   /tf_static                 imu0 -> cam0, imu0 -> cam1 from the calibration (transient local)
///   /mcvio/landmarks           sensor_msgs/PointCloud2 of the window's landmarks (world)
///   /mcvio/conflict            mcvio_msgs/MotionConflict per estimated frame
///   /mcvio/secondary_odometry  nav_msgs/Odometry of the conflicting frame while it is tracked
///   /mcvio/secondary_path      nav_msgs/Path of those poses (transient local), revised with
///                              /mcvio/path when a conflict window re-estimates the interval
/// The estimator sees what `mcvio run` gives it: every IMU sample up to a frame's stamp, then the
/// frame. A frame therefore waits until /imu0 has reached its stamp. Nothing is published before
/// the estimator is initialised. Bad input is logged with its topic and skipped; never fatal.
class BackendComponent {
 public:
  /// Throws mcvio::InputError for a missing or bad calibration, std::invalid_argument for bad options.
  BackendComponent(std::shared_ptr<dds::Node> node, BackendComponentOptions options);
  ~BackendComponent();
  /// End of stream: frames still waiting for IMU go to the estimator with the IMU there is.
  /// Returns when every frame received so far has been processed.
  void flush();
  BackendComponentStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mcvio::components
