#include <iostream>

#include "commands/command_context.hpp"
#include "mcvio/components/backend_component.hpp"
#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/dds/shutdown_signal.hpp"
#include "mcvio/pipeline/vio_pipeline.hpp"

namespace mcvio::cli {

void addBackendCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    std::string calib, config, mode;
    std::vector<std::string> remap;
    components::BackendComponentOptions component;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "backend",
      "Run the backend component: the sliding-window visual-inertial estimator on /imu0\n"
      "(sensor_msgs/Imu) and /mcvio/features (mcvio_msgs/FeatureFrame, from `mcvio frontend`).\n"
      "Publishes /mcvio/odometry (nav_msgs/Odometry world -> imu0, pose covariance in world axes),\n"
      "/mcvio/path, /tf (world -> imu0), /tf_static (imu0 -> cam0, cam1), /mcvio/landmarks\n"
      "(sensor_msgs/PointCloud2), /mcvio/conflict (mcvio_msgs/MotionConflict) and, while a\n"
      "conflicting frame is tracked, /mcvio/secondary_odometry and /mcvio/secondary_path (both paths\n"
      "are revised in place when a conflict window re-estimates an interval). Nothing is published\n"
      "before the estimator is initialised (it logs why it waits). Ctrl-C stops it and prints a summary.\n"
      "Each feature frame waits until /imu0 has reached its stamp, so with --lossless on the frontend,\n"
      "backend and player the poses are those of `mcvio run` on the same data.\n"
      "Examples:\n"
      "  mcvio backend --calib ../shared/data/euroc_V1_01_excerpt\n"
      "  mcvio backend --calib /tmp/elevator --config my_vio.yaml --mode reference --lossless\n"
      "  mcvio backend --calib /tmp/elevator --path-max 0 --landmarks-every 5 --world-frame odom\n"
      "  mcvio backend --calib DIR --remap /imu0:=/camera/imu --remap /mcvio/odometry:=/odom\n"
      "A lossless pipeline (a lossless player needs a reader of every topic it plays, e.g. the recorder):\n"
      "  mcvio backend --calib DIR --lossless &  mcvio frontend --calib DIR --lossless &\n"
      "  mcvio record -o /tmp/rec --all &  mcvio play DIR --lossless");
  cmd->add_option("--calib", opt->calib,
                  "EuRoC folder whose cam0/cam1/imu0 sensor.yaml give extrinsics and IMU noise, or Kalibr's\n"
                  "camchain-imucam YAML (file, or its folder) with its imu*.yaml beside it (whose rostopic, if any,\n"
                  "is read for /imu0 unless --remap names it), e.g. --calib ../shared/data/euroc_V1_01_excerpt")
      ->required();
  cmd->add_option("--config", opt->config,
                  "YAML with `estimator:` options (a `frontend:` section is allowed and ignored here), the same file "
                  "as `mcvio run --config`, e.g. --config my_vio.yaml (default: the shipped config/vio_pipeline.yaml, built in)");
  cmd->add_option("--mode", opt->mode,
                  "motion-conflict handling: reference (detect and report only), imu (IMU-dominated), selective "
                  "(drop the moving landmarks) or auto; overrides the config file, e.g. --mode selective "
                  "(default: the config file's, else reference)")
      ->check(CLI::IsMember({"reference", "imu", "selective", "auto"}));
  cmd->add_flag("--lossless", opt->component.lossless,
                "reliable keep-all topics and no frame dropped: offline pipelines that must match `mcvio run`");
  cmd->add_option("--world-frame", opt->component.world_frame, "frame id of the odometry, path, tf parent and landmarks")
      ->capture_default_str();
  cmd->add_option("--body-frame", opt->component.body_frame, "child frame of /mcvio/odometry and /tf (the IMU)")
      ->capture_default_str();
  cmd->add_option("--secondary-frame", opt->component.secondary_frame,
                  "child frame of /mcvio/secondary_odometry, the conflicting frame (a cabin, a vehicle)")
      ->capture_default_str();
  cmd->add_option("--landmarks-every", opt->component.landmarks_every_n_frames,
                  "publish /mcvio/landmarks every N estimated frames, 0 = never, e.g. --landmarks-every 5")
      ->check(finiteAtLeastZero())
      ->capture_default_str();
  cmd->add_option("--path-max", opt->component.max_path_poses,
                  "keep the newest N poses in /mcvio/path and /mcvio/secondary_path, 0 = all (every message\n"
                  "grows with the run)")
      ->check(finiteAtLeastZero())
      ->capture_default_str();
  cmd->add_option("--max-imu-wait", opt->component.max_imu_wait_s,
                  "without --lossless: a frame waits at most this long for /imu0 to reach its stamp [s]")
      ->check(finiteAtLeastZero())
      ->capture_default_str();
  addRemapOption(cmd, opt->remap, "/imu0:=/camera/imu");
  cmd->callback([opt, &ctx] {
    const auto remapping = TopicRemapping::parse(opt->remap);
    auto o = opt->component;
    o.calibration_dir = opt->calib;
    if (!opt->config.empty()) o.estimator = pipeline::VioPipelineOptions::fromYamlFile(opt->config).estimator;
    if (!opt->mode.empty()) o.estimator.conflict.mode = conflict::resolutionModeFromString(opt->mode, "--mode");
    auto participant = dds::Participant::create(ctx.participantOptions("mcvio_backend"));
    auto node = participant->createNode("backend", "/mcvio", remapping);
    components::BackendComponent backend(node, o);
    warnUnusedRemapRules(*node, "backend");
    std::cerr << "mcvio backend: running; Ctrl-C to stop\n";
    while (!dds::ShutdownSignal::waitFor(std::chrono::seconds(1))) {
    }
    backend.flush();  // frames still waiting for IMU that will not come now
    const auto s = backend.stats();
    std::cerr << "mcvio backend: " << s.frames_received << " feature frames (" << s.frames_rejected << " rejected, "
              << s.frames_dropped << " dropped, " << s.frames_not_accepted << " refused by the estimator), "
              << s.poses_published << " poses, " << s.not_initialized << " before initialisation, " << s.resets
              << " resets, " << s.conflict_frames << " in conflict; " << s.imu_received << " IMU samples ("
              << s.imu_rejected << " rejected); latency mean " << s.latency_ms_mean << " ms, max " << s.latency_ms_max
              << " ms; estimator CPU mean " << s.estimator_cpu_ms_mean << " ms\n";
  });
}

}  // namespace mcvio::cli
