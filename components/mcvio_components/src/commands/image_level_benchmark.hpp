#pragma once
#include <string>
#include <vector>

#include "mcvio/evaluation/benchmark_result.hpp"
#include "mcvio/evaluation/benchmark_suite.hpp"
#include "mcvio/sim/camera_renderer.hpp"

namespace mcvio::cli {

/// `mcvio bench --level images`: the benchmark on rendered images through the whole offline
/// pipeline. Each planned sequence is rendered with mcvio_sim to WORK/data/<name> (a EuRoC folder
/// with conflict labels), every mode runs `mcvio run` (runOffline) into WORK/runs/<name>/<mode>,
/// and BenchmarkSuite::evaluateSequence measures the runs as at feature level. With a semi-real
/// source, an extra sequence is rendered along its recorded ground truth with its real IMU and
/// the injected-overlay experiment (`mcvio inject --scenario overlay`) is added on top of it, with
/// `reference` also run on the sequence without the overlay (the clean floor of the report; a
/// scenario with the clean office's trajectory and IMU gets that office's reference as its floor).
/// Real EuRoC folders can be added as clean sequences. Rendering takes about a minute per minute
/// of sequence, so this is for a few sequences.
class ImageLevelBenchmark {
 public:
  struct Options {
    evaluation::BenchmarkOptions suite;  ///< modes, scenarios, seeds, durations (and the sweep if set)
    std::string work_dir;                ///< rendered data and per-mode run folders
    std::string pipeline_config;         ///< VioPipelineOptions YAML; empty: defaults
    /// EuRoC folder whose ground truth and IMU drive the semi-real overlay sequence; empty: none.
    std::string semi_real_dir;
    double overlay_onset_s = 5.0;     ///< after the first frame of the semi-real sequence
    double overlay_duration_s = 4.0;
    /// Real EuRoC folders run as clean sequences (scenario "none"): every frame is labelled
    /// conflict-free unless the folder has mav0/conflict_labels.csv.
    std::vector<std::string> real_dirs;
    /// Rig the scenarios are rendered with (a folder with cam0/cam1/imu0 sensor.yaml, as `mcvio
    /// sim --calib`); empty: EuRoC V1_01's. The semi-real overlay keeps its recording's rig.
    std::string rig_calibration_dir;
    sim::TextureFilter texture_filter = sim::TextureFilter::kIsotropic;  ///< of every rendered sequence
  };

  explicit ImageLevelBenchmark(Options options);
  /// Renders, runs and evaluates everything; `progress` as BenchmarkSuite::run. Throws
  /// mcvio::InputError for unreadable input or unwritable folders.
  evaluation::BenchmarkResult run(const evaluation::BenchmarkSuite::Progress& progress = {}) const;

 private:
  /// `reference` on the overlay's base sequence (the same images without the overlay), into
  /// WORK/runs/<name>_base/reference: its ATE pos+yaw is the floor no mode can go below.
  double cleanFloor(const std::string& base_dir, const evaluation::BenchmarkSequence& sequence) const;

  Options options_;
};

}  // namespace mcvio::cli
