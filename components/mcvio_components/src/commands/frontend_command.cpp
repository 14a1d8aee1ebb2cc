#include <iostream>
#include <thread>

#include "commands/command_context.hpp"
#include "mcvio/components/frontend_component.hpp"
#include "mcvio/dds/shutdown_signal.hpp"

namespace mcvio::cli {

void addFrontendCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    std::string calib, config;
    bool tracks_image = false, lossless = false;
    std::string image_transport = "raw";
    std::vector<std::string> remap;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "frontend",
      "Run the frontend component: stereo KLT tracking of /cam0/image_raw + /cam1/image_raw with gyro\n"
      "prediction from /imu0; publishes /mcvio/features (mcvio_msgs/FeatureFrame), keeping tracks that\n"
      "disagree with the dominant motion (labelled inconsistent) for the backend's conflict detection.\n"
      "Examples:\n"
      "  mcvio frontend --calib ../shared/data/euroc_V1_01_excerpt --tracks-image\n"
      "  mcvio frontend --calib /tmp/elevator --config config/frontend.yaml --lossless\n"
      "  mcvio frontend --calib DIR --remap /cam0/image_raw:=/camera/infra1/image_rect_raw \\\n"
      "    --remap /cam1/image_raw:=/camera/infra2/image_rect_raw --remap /imu0:=/camera/imu   # a driver's topics\n"
      "  mcvio frontend --calib DIR --image-transport compressed   # jpeg/png on /cam0/image_raw/compressed, ...\n"
      "Images may be mono8, mono16, rgb8, bgr8, rgba8, bgra8, Bayer (bayer_rggb8, ...) or yuv422, or\n"
      "compressed jpeg or png; they are tracked as 8-bit grey.");
  cmd->add_option("--calib", opt->calib,
                  "stereo calibration: a EuRoC folder (cam0/cam1/imu0 sensor.yaml), or Kalibr's camchain-imucam\n"
                  "YAML (file, or its folder) with its imu*.yaml beside it; Kalibr's timeshift_cam_imu is applied, and\n"
                  "its rostopic names the topics to read (unless --remap names them)");
  cmd->add_option("--config", opt->config, "YAML with frontend options (see config/frontend.yaml)");
  cmd->add_flag("--tracks-image", opt->tracks_image, "also publish /mcvio/tracks_image (rgb8) for RViz/Foxglove");
  cmd->add_flag("--lossless", opt->lossless, "reliable keep-all topics, for lossless offline pipelines");
  cmd->add_option("--image-transport", opt->image_transport,
                  "raw: sensor_msgs/Image on /cam0/image_raw and /cam1/image_raw; compressed:\n"
                  "sensor_msgs/CompressedImage (jpeg, png) on /cam0/image_raw/compressed and /cam1/image_raw/compressed,\n"
                  "as ROS 2's image_transport names them (--remap renames the base topics)")
      ->check(CLI::IsMember({"raw", "compressed"}))
      ->capture_default_str();
  addRemapOption(cmd, opt->remap, "/imu0:=/camera/imu");
  cmd->callback([opt, &ctx] {
    const auto remapping = TopicRemapping::parse(opt->remap);
    components::FrontendComponentOptions o;
    if (!opt->config.empty()) o.tracker = frontend::FrontendOptions::fromFile(opt->config);
    o.calibration_dir = opt->calib;
    o.publish_tracks_image = opt->tracks_image;
    o.lossless = opt->lossless;
    o.image_transport = opt->image_transport;
    auto participant = dds::Participant::create(ctx.participantOptions("mcvio_frontend"));
    auto node = participant->createNode("frontend", "/mcvio", remapping);
    components::FrontendComponent frontend(node, o);
    warnUnusedRemapRules(*node, "frontend");
    std::cerr << "mcvio frontend: running; Ctrl-C to stop\n";
    while (!dds::ShutdownSignal::waitFor(std::chrono::seconds(1))) {
    }
    const auto s = frontend.stats();
    std::cerr << "mcvio frontend: " << s.pairs_received << " stereo pairs, " << s.frames_published << " feature frames, "
              << s.frames_skipped << " skipped, " << s.pairs_dropped << " dropped, " << s.bad_images
              << " bad images, " << s.unpaired_images << " unpaired\n";
  });
}

}  // namespace mcvio::cli
