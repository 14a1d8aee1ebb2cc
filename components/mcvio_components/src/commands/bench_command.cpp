// `mcvio bench`: the MC-VIO benchmark suite at feature level, one report.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include <spdlog/spdlog.h>

#include "commands/command_context.hpp"
#include "commands/image_level_benchmark.hpp"
#include "mcvio/evaluation/benchmark_report_writer.hpp"
#include "mcvio/evaluation/benchmark_suite.hpp"
#include "mcvio/pipeline/vio_pipeline.hpp"

namespace mcvio::cli {

namespace {

namespace ev = mcvio::evaluation;

}  // namespace

void addBenchCommand(CLI::App& app, CommandContext& ctx) {
  struct Options {
    std::string out, level = "features", config, semi_real, calib, texture_filter;
    double overlay_onset_s = 5.0, overlay_duration_s = 4.0;
    std::vector<std::string> modes, scenarios, sweep_scenarios, real;
    std::vector<std::uint64_t> seeds;
    std::vector<double> sweep;
    bool no_sweep = false;
    double sequence_s = 0, onset_s = 0, conflict_s = 0, sweep_tail_s = 0, rpe_delta_s = 0;
    int jobs = 1;
    bool quick = false, oracle = false, no_plots = false, quiet = false, verbose = false;
  };
  auto opt = std::make_shared<Options>();
  const ev::BenchmarkOptions defaults;
  auto* cmd = app.add_subcommand(
      "bench",
      "Run the MC-VIO benchmark suite and write one report. For every scenario (none, elevator, vehicle,\n"
      "self_occlusion, pedestrian, slow_object) and seed, the feature-level simulator makes stereo tracks,\n"
      "IMU, ground truth and per-frame conflict labels; one estimator per resolution mode (reference,\n"
      "imu, selective, auto) runs on it, the modes taking each frame in turn so that their CPU times\n"
      "see the same host load. Measured per run: ATE RMSE after position+yaw and SE(3) alignment, ATE\n"
      "over the conflict frames, RPE (1 s), per-frame detection TPR/FPR and ROC, how late the\n"
      "detection came and how long it stayed on after the conflict (seconds), median and mean backend\n"
      "CPU per frame, the elevator's vertical ride displacement (estimate and secondary frame vs\n"
      "truth), the vehicle's travel (its secondary frame vs the body's, in the ground truth's frame);\n"
      "reductions and added CPU (mean per frame) versus `reference` on the same sequence; ATE versus conflict\n"
      "duration for the elevator and vehicle rides; pass/fail against the MC-VIO targets (conflict ATE\n"
      ">= 80% and RPE >= 40% below reference, clean ATE at most 5% above, TPR >= 0.95 at FPR <= 0.02,\n"
      "elevator ride within 5%, the cabin's and the vehicle's own motion within 10%, added backend\n"
      "CPU <= 20%).\n"
      "Writes OUT/bench.json, OUT/bench.md (also printed), ate_by_scenario.png, rpe_by_scenario.png and\n"
      "ate_vs_duration_<scenario>.png; one progress line per run goes to stderr.\n"
      "At feature level (default) the simulator's ground-truth track labels are cleared before the\n"
      "estimator sees them unless --oracle-track-labels. `--level images` renders each sequence with\n"
      "mcvio_sim (OUT/images/data/<sequence>, about a minute per minute of sequence) and runs the whole\n"
      "offline pipeline per mode (`mcvio run`, OUT/images/runs/<sequence>/<mode>); it skips the duration\n"
      "sweep unless --duration-sweep is given, and with --semi-real adds the injected-overlay experiment:\n"
      "the office rendered along that EuRoC folder's ground truth with its real IMU, and `mcvio inject\n"
      "--scenario overlay` on top (sequence overlay_semi_real), plus `reference` on the same images\n"
      "without the overlay: the clean floor no mode can go below (report section \"Clean floor\"; a\n"
      "scenario rendered along the clean office's trajectory and IMU has that office as its floor);\n"
      "--real adds recorded EuRoC folders as clean sequences.\n"
      "Examples:\n"
      "  mcvio bench --out /tmp/bench                          the whole suite (tens of minutes)\n"
      "  mcvio bench --out /tmp/bench --jobs 2                 two sequences at a time\n"
      "  mcvio bench --quick --out /tmp/bench_quick            25 s sequences, none+elevator, reference+auto\n"
      "  mcvio bench --out /tmp/b --scenarios elevator,vehicle --modes reference,imu --seeds 1,2 --no-sweep\n"
      "  mcvio bench --out /tmp/b --scenarios none --duration-sweep 0,10,20,30,40 --sweep-scenarios elevator\n"
      "  mcvio bench --level images --out /tmp/bi --scenarios none,elevator --modes reference,auto \\\n"
      "              --sequence-duration 30 --onset 10 --conflict-duration 8 --semi-real ../shared/data/euroc_V1_01_excerpt \\\n"
      "              --real ../shared/data/euroc_V1_01_excerpt");
  cmd->add_option("--out", opt->out, "report folder (created; bench.* and the figures in it are replaced)")->required();
  cmd->add_option("--level", opt->level,
                  "features: FeatureSimulator tracks straight into the estimator (fast: the whole suite in tens of\n"
                  "minutes); images: rendered images through frontend + estimator (slow; pick a few sequences)")
      ->check(CLI::IsMember({"features", "images"}))
      ->capture_default_str();
  cmd->add_option("--semi-real", opt->semi_real,
                  "images level: EuRoC folder whose ground truth and IMU drive the injected-overlay sequence\n"
                  "(e.g. ../shared/data/euroc_V1_01_excerpt); without it the overlay experiment is not run");
  cmd->add_option("--real", opt->real,
                  "images level: a real EuRoC folder run as a clean sequence (repeatable), e.g.\n"
                  "../shared/data/euroc_V1_01_excerpt; frames count as conflict-free unless it has conflict labels");
  cmd->add_option("--overlay-onset", opt->overlay_onset_s, "images level: overlay onset after the first frame [s]")
      ->capture_default_str();
  cmd->add_option("--overlay-duration", opt->overlay_duration_s, "images level: how long the overlay is seen [s]")
      ->capture_default_str();
  cmd->add_option("--calib", opt->calib,
                  "images level: render the scenarios with this rig, a folder with cam0/cam1/imu0 sensor.yaml as for\n"
                  "`mcvio sim --calib` (default: EuRoC V1_01's), e.g. --calib /data/fisheye_rig");
  cmd->add_option("--texture-filter", opt->texture_filter,
                  "images level: isotropic (default) or anisotropic texture filtering of the rendered images\n"
                  "(`mcvio sim --help`; anisotropic for wide lenses), e.g. --texture-filter anisotropic");
  cmd->add_option("--config", opt->config,
                  "images level: VioPipelineOptions YAML for `mcvio run` (default: the shipped config/vio_pipeline.yaml,\n"
                  "built in); feature level: its `estimator:` section (default: the library defaults), with\n"
                  "observation_sigma_px set to the simulator's pixel noise");
  cmd->add_option("--modes", opt->modes, "resolution modes, comma separated; must include reference (default: all four)")
      ->delimiter(',');
  cmd->add_option("--scenarios", opt->scenarios,
                  "scenarios, comma separated (default: none,elevator,vehicle,self_occlusion,pedestrian,slow_object)")
      ->delimiter(',');
  cmd->add_option("--seeds", opt->seeds, "simulator seeds, comma separated; one sequence per scenario and seed (default: 1)")
      ->delimiter(',');
  cmd->add_option("--duration-sweep", opt->sweep,
                  "conflict durations [s] of the ATE-versus-duration sweep, comma separated (default: 0,10,20,30,40;\n"
                  "each sequence lasts onset + duration + --sweep-tail; first seed only)")
      ->delimiter(',');
  cmd->add_flag("--no-sweep", opt->no_sweep, "skip the duration sweep");
  cmd->add_option("--sweep-scenarios", opt->sweep_scenarios, "rides to sweep: elevator, vehicle (default: both)")
      ->delimiter(',');
  cmd->add_option("--sequence-duration", opt->sequence_s, "length of each scenario sequence [s] (default: 60)");
  cmd->add_option("--onset", opt->onset_s, "conflict onset after the first frame [s] (default: 20)");
  cmd->add_option("--conflict-duration", opt->conflict_s, "conflict length of the scenario sequences [s] (default: 15)");
  cmd->add_option("--sweep-tail", opt->sweep_tail_s, "seconds after the conflict in sweep sequences (default: 15)");
  cmd->add_option("--rpe-delta-s", opt->rpe_delta_s, "RPE pair separation [s] (default: 1)");
  cmd->add_option("--jobs,-j", opt->jobs, "feature level: sequences simulated and estimated at a time (default: 1)");
  cmd->add_flag("--quick", opt->quick,
                "a small suite: 25 s sequences, conflict 8 s from 8 s, scenarios none,elevator, modes\n"
                "reference,auto, no sweep; options given explicitly still apply");
  cmd->add_flag("--oracle-track-labels", opt->oracle,
                "keep the simulator's ground-truth consistent/inconsistent track labels (an oracle frontend)");
  cmd->add_flag("--no-plots", opt->no_plots, "write only bench.json and bench.md");
  cmd->add_flag("-q,--quiet", opt->quiet, "no progress lines and no printed report");
  cmd->add_flag("-v,--verbose", opt->verbose, "estimator log messages (conflict intervals, resets) on stderr");

  cmd->callback([opt, cmd, &ctx] {
    ev::BenchmarkOptions o = opt->quick ? ev::BenchmarkOptions::quick() : ev::BenchmarkOptions{};
    auto given = [&](const char* name) { return cmd->get_option(name)->count() > 0; };
    if (given("--modes")) o.modes = opt->modes;
    if (given("--scenarios")) {  // --scenarios '' runs no simulator scenario (e.g. only --real)
      o.scenarios.clear();
      for (const auto& sc : opt->scenarios)
        if (!sc.empty()) o.scenarios.push_back(sc);
    }
    if (given("--seeds")) o.seeds = opt->seeds;
    if (given("--duration-sweep")) o.sweep_durations_s = opt->sweep;
    else if (opt->level == "images") o.sweep_durations_s.clear();
    if (opt->no_sweep) o.sweep_durations_s.clear();
    if (given("--sweep-scenarios")) o.sweep_scenarios = opt->sweep_scenarios;
    if (given("--sequence-duration")) o.sequence_duration_s = opt->sequence_s;
    if (given("--onset")) o.onset_s = opt->onset_s;
    if (given("--conflict-duration")) o.conflict_duration_s = opt->conflict_s;
    if (given("--sweep-tail")) o.sweep_tail_s = opt->sweep_tail_s;
    if (given("--rpe-delta-s")) o.rpe_delta_s = opt->rpe_delta_s;
    o.jobs = opt->jobs;
    o.oracle_track_labels = opt->oracle;
    if (opt->level == "features" && !opt->config.empty())
      o.estimator = pipeline::VioPipelineOptions::fromYamlFile(opt->config).estimator;
    const ev::BenchmarkSuite suite(o);  // validates: std::invalid_argument -> exit 2 naming the option

    if (ctx.log_level.empty()) spdlog::set_level(opt->verbose ? spdlog::level::info : spdlog::level::err);
    const std::size_t sequences =
        suite.plan().size() + (opt->level == "images" ? (opt->semi_real.empty() ? 0 : 1) + opt->real.size() : 0);
    if (opt->level != "images" && (!opt->semi_real.empty() || !opt->real.empty()))
      throw CommandExit{2, "bench: --semi-real and --real need --level images"};
    if (opt->level != "images" && (!opt->calib.empty() || !opt->texture_filter.empty()))
      throw CommandExit{2, "bench: --calib and --texture-filter need --level images"};
    const sim::TextureFilter texture_filter = opt->texture_filter.empty()
                                                  ? sim::TextureFilter::kIsotropic
                                                  : sim::textureFilterFromString(opt->texture_filter, "--texture-filter");
    if (sequences == 0) throw CommandExit{2, "bench: nothing to run (no scenarios, no sweep, no recorded sequences)"};
    if (!opt->quiet)
      std::cerr << "mcvio bench (" << (opt->level == "images" ? "image" : "feature") << " level): " << sequences << " sequences x " << o.modes.size()
                << " modes = " << sequences * o.modes.size() << " runs"
                << (opt->level == "images" && !opt->semi_real.empty() ? " + reference on the overlay's clean base" : "")
                << (opt->level == "features" ? ", " + std::to_string(o.jobs) + " sequence(s) at a time" : std::string())
                << (opt->level == "images" ? std::string(", rig ") + (opt->calib.empty() ? "EuRoC V1_01" : opt->calib) +
                                                 ", texture filter " + sim::toString(texture_filter)
                                           : std::string())
                << "\n";
    const auto progress = [&](std::size_t done, std::size_t total, const std::string& line) {
      if (!opt->quiet) std::cerr << "[" << done << "/" << total << "] " << line << std::endl;
    };
    ev::BenchmarkResult result;
    if (opt->level == "images") {
      ImageLevelBenchmark::Options io;
      io.suite = o;
      io.work_dir = (std::filesystem::path(opt->out) / "images").string();
      io.pipeline_config = opt->config;
      io.semi_real_dir = opt->semi_real;
      io.overlay_onset_s = opt->overlay_onset_s;
      io.overlay_duration_s = opt->overlay_duration_s;
      io.real_dirs = opt->real;
      io.rig_calibration_dir = opt->calib;
      io.texture_filter = texture_filter;
      result = ImageLevelBenchmark(io).run(progress);
    } else {
      result = suite.run(progress);
    }
    const auto files = ev::BenchmarkReportWriter::write(result, opt->out, !opt->no_plots);
    if (!opt->quiet) {
      std::cout << ev::BenchmarkReportWriter::toMarkdown(result);
      std::cerr << "mcvio bench: wrote";
      for (const auto& f : files) std::cerr << " " << f;
      std::cerr << "\n";
    }
  });
}

}  // namespace mcvio::cli
