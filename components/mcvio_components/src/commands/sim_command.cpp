#include <iostream>
#include <optional>

#include "commands/command_context.hpp"
#include "mcvio/core/progress_bar.hpp"
#include "mcvio/sim/image_injector.hpp"
#include "mcvio/sim/simulator.hpp"

namespace mcvio::cli {

void addSimCommand(CLI::App& app, CommandContext&) {
  struct Options {
    std::string config, scenario = "none", out, trajectory, imu, calib, texture_filter;
    double duration = 60;
    // Unset unless given, so that a given value (negative, NaN) reaches validate() and is rejected.
    std::optional<double> onset, scenario_duration, coverage;
    std::uint64_t seed = 1;
    bool overwrite = false, exact_imu = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "sim",
      "Render a stereo-inertial EuRoC sequence of a textured world, optionally with a motion conflict.\n"
      "Scenarios: none, elevator, vehicle, self_occlusion, pedestrian, slow_object. Writes cam0/cam1\n"
      "PNGs, imu0, ground truth (200 Hz) and mav0/conflict_labels.csv. Deterministic for a seed.\n"
      "Examples:\n"
      "  mcvio sim --scenario elevator --duration 60 --onset 20 --scenario-duration 15 --out /tmp/elevator\n"
      "  mcvio sim --scenario pedestrian --trajectory ../shared/data/euroc_V1_01_excerpt/mav0/state_groundtruth_estimate0/data.csv \\\n"
      "            --imu ../shared/data/euroc_V1_01_excerpt/mav0/imu0/data.csv --calib ../shared/data/euroc_V1_01_excerpt --out /tmp/semi\n"
      "  mcvio sim --config config/sim/elevator.yaml      # every option of the simulator in YAML");
  cmd->add_option("--config", opt->config, "YAML file with SimulatorOptions; flags given here override it");
  cmd->add_option("--scenario", opt->scenario, "none|elevator|vehicle|self_occlusion|pedestrian|slow_object")
      ->capture_default_str();
  cmd->add_option("--duration", opt->duration, "sequence length [s] (synthetic trajectory)")->capture_default_str();
  cmd->add_option("--onset", opt->onset, "conflict start, seconds after the first frame (default 20)");
  cmd->add_option("--scenario-duration", opt->scenario_duration, "conflict length [s] (default 15)");
  cmd->add_option("--coverage", opt->coverage, "fraction of the view the conflicting motion covers (default 0.7)");
  cmd->add_option("--seed", opt->seed, "random seed (world, textures, noise)")
      ->check(finiteAtLeastZero())
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "output EuRoC folder")->required();
  cmd->add_flag("--overwrite", opt->overwrite, "replace an existing output");
  cmd->add_flag("--exact-imu", opt->exact_imu, "no IMU noise or bias random walk");
  cmd->add_option("--trajectory", opt->trajectory, "semi-real: EuRoC ground-truth CSV to render along");
  cmd->add_option("--imu", opt->imu, "semi-real: real IMU CSV to keep");
  cmd->add_option("--calib", opt->calib, "folder with cam0/cam1/imu0 sensor.yaml (default: EuRoC V1_01)");
  cmd->add_option("--texture-filter", opt->texture_filter,
                  "isotropic (default: one mip level per pixel; overstates the blur towards a wide lens's edge)\n"
                  "or anisotropic (the pixel's exact footprint, up to 8 samples along its long axis: sharper\n"
                  "and truer, most of all through fisheye lenses; renders about 1.8x slower),\n"
                  "e.g. --calib /data/fisheye_rig --texture-filter anisotropic");
  cmd->callback([opt] {
    sim::SimulatorOptions o = opt->config.empty() ? sim::SimulatorOptions{} : sim::SimulatorOptions::fromYamlFile(opt->config);
    o.output_dir = opt->out;
    o.overwrite = o.overwrite || opt->overwrite;
    o.seed = opt->seed;
    o.duration_s = opt->duration;
    o.scenario.kind = sim::scenarioKindFromString(opt->scenario);
    if (opt->onset) o.scenario.onset_s = *opt->onset;
    if (opt->scenario_duration) o.scenario.duration_s = *opt->scenario_duration;
    if (opt->coverage) o.scenario.coverage = *opt->coverage;
    if (opt->exact_imu) o.imu_noise_enabled = false;
    if (!opt->trajectory.empty()) o.groundtruth_csv = opt->trajectory;
    if (!opt->imu.empty()) o.imu_csv = opt->imu;
    if (!opt->calib.empty()) o.calibration_dir = opt->calib;
    if (!opt->texture_filter.empty()) o.texture_filter = sim::textureFilterFromString(opt->texture_filter, "--texture-filter");
    o.validate();
    sim::Simulator simulator(o);
    ProgressBar bar("sim", simulator.frameTimes().size());
    const auto s = simulator.writeDataset([&](std::size_t done, std::size_t total) {
      bar.update(done, std::to_string(done) + "/" + std::to_string(total) + " frames");
    });
    bar.finish();
    std::cerr << "mcvio sim: " << s.frames << " stereo frames (" << s.conflict_frames << " in conflict), "
              << s.imu_samples << " IMU samples, " << s.ground_truth_rows << " ground-truth rows in "
              << s.total_seconds << " s (" << (s.total_seconds > 0 ? s.frames / s.total_seconds : 0.0)
              << " stereo frames/s) -> " << o.output_dir << "\n";
  });
}

void addInjectCommand(CLI::App& app, CommandContext&) {
  struct Options {
    std::string config, scenario = "overlay", in, out;
    std::optional<double> onset, duration, depth;
    bool overwrite = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "inject",
      "Insert an artificial textured image moving against the true motion into an existing EuRoC\n"
      "folder, consistently in both cameras, and write labels (the dissertation's EuRoC experiment).\n"
      "Example: mcvio inject --scenario overlay --onset 1 --duration 3 ../shared/data/euroc_V1_01_excerpt /tmp/injected");
  cmd->add_option("--scenario", opt->scenario, "overlay (a textured plane in front of the rig) or occluder")
      ->check(CLI::IsMember({"overlay", "occluder"}))
      ->capture_default_str();
  cmd->add_option("--config", opt->config, "YAML file with InjectOptions; flags override it");
  cmd->add_option("--onset", opt->onset, "seconds after the first frame (default 1)");
  cmd->add_option("--duration", opt->duration, "seconds the image is visible (default 3)");
  cmd->add_option("--depth", opt->depth, "distance of the plane in front of cam0 [m] (default 1.2)");
  cmd->add_flag("--overwrite", opt->overwrite, "replace an existing output");
  cmd->add_option("in_dir", opt->in, "input EuRoC folder")->required();
  cmd->add_option("out_dir", opt->out, "output EuRoC folder")->required();
  cmd->callback([opt] {
    sim::InjectOptions o = opt->config.empty() ? sim::InjectOptions{} : sim::InjectOptions::fromYamlFile(opt->config);
    o.input_dir = opt->in;
    o.output_dir = opt->out;
    o.overwrite = o.overwrite || opt->overwrite;
    if (opt->onset) o.onset_s = *opt->onset;
    if (opt->duration) o.duration_s = *opt->duration;
    if (opt->depth) o.depth_m = *opt->depth;
    if (opt->scenario == "occluder") {
      // An occluder is a large plane close to the rig that barely moves: it hides, not misleads.
      o.depth_m = opt->depth ? *opt->depth : 0.5;
      o.width_m = 1.2;
      o.height_m = 0.9;
      o.velocity_mps = Eigen::Vector3d(0.02, 0.0, 0.0);
      o.sway_amplitude_m = 0.0;
      o.spin_rate = 0.0;
      o.motion_name = "occluder";
    }
    o.validate();
    ProgressBar bar("inject", 0);
    const auto s = sim::runInjection(o, [&](std::size_t done, std::size_t total) {
      bar.update(done, std::to_string(done) + "/" + std::to_string(total) + " frames");
    });
    bar.finish();
    std::cerr << "mcvio inject: " << s.frames << " frames, " << s.injected_frames << " with the injected image, "
              << s.warnings << " input rows skipped -> " << o.output_dir << "\n";
  });
}

}  // namespace mcvio::cli
