#include <iostream>

#include "commands/command_context.hpp"
#include "mcvio/dds/shutdown_signal.hpp"
#include "mcvio/interfaces/message_registry.hpp"
#include "mcvio/pipeline/offline_run.hpp"

namespace mcvio::cli {

void addRunCommand(CLI::App& app, CommandContext&) {
  auto opt = std::make_shared<pipeline::OfflineRunOptions>();
  auto quiet = std::make_shared<bool>(false);
  auto remap = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand(
      "run",
      "Run the whole VIO (frontend + sliding-window estimator) over a EuRoC folder without DDS,\n"
      "deterministically. Writes OUT/trajectory.tum (t x y z qx qy qz qw: imu0 in world, t in s; the\n"
      "final estimate: when a conflict window re-estimates earlier frames after an IMU-dominated\n"
      "interval, the per-frame output is kept in OUT/trajectory_online.tum), OUT/conflict.csv\n"
      "(per-frame motion-conflict statistics and their combined evidence score, with each interval's\n"
      "detected start and its bounds in hindsight), OUT/secondary.tum (the conflicting frame, e.g. an\n"
      "elevator cabin, in the world while it is tracked; final like trajectory.tum, per frame in\n"
      "OUT/secondary_online.tum when revised) and OUT/stats.json (per-stage CPU time,\n"
      "features, new and re-identified tracks, keyframes, resets, peak memory). Ctrl-C stops after the\n"
      "frame in hand (exit 130) and keeps what was written, stats.json saying \"completed\": false.\n"
      "Examples:\n"
      "  mcvio run --dataset ../shared/data/euroc_V1_01_excerpt --out /tmp/run\n"
      "  mcvio run --dataset /tmp/elevator --out /tmp/run_elevator --mode auto\n"
      "  mcvio run --dataset /tmp/elevator --out /tmp/run_elevator --config my_vio.yaml\n"
      "  mcvio run --dataset /tmp/recorded_bag --calib ../shared/data/euroc_V1_01_excerpt --out /tmp/run_bag\n"
      "A bag with /mcvio/features (the frontend's output) and /imu0 but no images runs the estimator alone\n"
      "on the recorded features: on the bag of `mcvio demo` it gives exactly what the DDS backend published,\n"
      "and other modes or options can be tried on the same input:\n"
      "  mcvio run --dataset /tmp/mcvio_demo/elevator/bag --calib /tmp/mcvio_demo/elevator/data --mode reference --out /tmp/ref\n"
      "A bag from other drivers: --remap names its topics; images may be sensor_msgs/Image in mono8, mono16,\n"
      "rgb8, bgr8, rgba8, bgra8, Bayer or yuv422, or sensor_msgs/CompressedImage (jpeg, png), tracked as grey:\n"
      "  mcvio run --dataset /data/d435i_bag --calib /data/d435i_euroc --out /tmp/d435i \\\n"
      "    --remap /cam0/image_raw:=/camera/infra1/image_rect_raw --remap /cam1/image_raw:=/camera/infra2/image_rect_raw \\\n"
      "    --remap /imu0:=/camera/imu");
  cmd->add_option("--dataset", opt->dataset_dir,
                  "EuRoC folder (holding mav0/), or a rosbag2 bag with /cam0/image_raw, /cam1/image_raw, /imu0\n"
                  "(or with /mcvio/features and /imu0: the estimator alone)")
      ->required();
  cmd->add_option("--calib", opt->calibration_dir,
                  "stereo calibration (required for bags): a EuRoC folder's sensor.yaml files, or Kalibr's\n"
                  "camchain-imucam YAML (file, or its folder) with its imu*.yaml beside it (timeshift_cam_imu applied;\n"
                  "on a bag, the topics rostopic names are read when the bag has them, unless --remap names them)");
  cmd->add_option("--out", opt->output_dir, "output folder (created)")->required();
  cmd->add_option("--config", opt->config_file,
                  "YAML with `frontend:` and `estimator:` option sections; keys left out keep the built-in defaults\n"
                  "(default: the shipped share/mcvio_pipeline/config/vio_pipeline.yaml, built in)");
  cmd->add_option("--mode", opt->mode,
                  "motion-conflict handling: reference (detect and report only), imu (IMU-dominated: drop the\n"
                  "conflicting visual residuals, hold the biases), selective (eliminate the landmarks that move;\n"
                  "hold the biases too once few static landmarks are left), auto (selective while enough static\n"
                  "landmarks remain, IMU-dominated otherwise);\n"
                  "default: the config's estimator.conflict.mode, else reference")
      ->check(CLI::IsMember({"reference", "imu", "selective", "auto"}));
  cmd->add_flag("-q,--quiet", *quiet, "no progress bar");
  addRemapOption(cmd, *remap, "/imu0:=/camera/imu (bags only: which bag topic is /cam0/image_raw, /cam1/image_raw,\n"
                              "  /imu0 or /mcvio/features)");
  cmd->callback([opt, quiet, remap] {
    opt->progress = !*quiet;
    opt->remapping = TopicRemapping::parse(*remap);
    // Bags from before Iron (sqlite3 without message_definitions) are read with these.
    for (const auto& d : interfaces::MessageRegistry::all())
      opt->known_message_definitions.emplace(std::string(d.name), std::string(d.full_definition));
    // Ctrl-C stops after the frame in hand and keeps what was written; a second one ends at once.
    opt->stop_requested = [] { return dds::ShutdownSignal::requested(); };
    pipeline::OfflineRunSummary s;
    try {
      s = pipeline::runOffline(*opt);
    } catch (const pipeline::RunInterrupted& e) {
      throw CommandExit{130, std::string("run: ") + e.what() + "; " + opt->output_dir +
                                 " keeps the frames done (stats.json says \"completed\": false)"};
    }
    // Every frame is one of: a pose, waiting to initialise, turned down by the estimator, or
    // skipped by the frontend (its image could not be used).
    std::cerr << "mcvio run: " << s.frames << " frames, " << s.estimated << " poses";
    if (s.not_initialized) std::cerr << ", " << s.not_initialized << " before initialisation";
    if (s.rejected) std::cerr << ", " << s.rejected << " rejected by the estimator";
    std::cerr << ", " << s.skipped << " skipped by the frontend, " << s.resets << " resets in " << s.wall_seconds
              << " s (" << s.data_seconds << " s of data, " << (s.wall_seconds > 0 ? s.data_seconds / s.wall_seconds : 0.0)
              << "x real time) -> " << opt->output_dir << "/trajectory.tum\n";
    for (const auto& reason : s.skip_reasons) std::cerr << "mcvio run: skipped: " << reason << "\n";
    if (s.skipped > s.skip_reasons.size()) std::cerr << "mcvio run: every skip reason: " << opt->output_dir << "/stats.json\n";
    if (s.rejected) std::cerr << "mcvio run: rejected, the first: " << s.first_rejection << "\n";
    if (s.estimated == 0) {
      throw CommandExit{1, "run: no pose was estimated (" + std::to_string(s.not_initialized) +
                               " frames waited to initialise; see the warnings above and " + opt->output_dir +
                               "/stats.json)"};
    }
  });
}

}  // namespace mcvio::cli
