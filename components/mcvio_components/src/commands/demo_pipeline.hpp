#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "mcvio/dds/participant.hpp"
#include "mcvio/evaluation/ride_measurement.hpp"

namespace mcvio::cli {

/// `mcvio demo`: the whole system on simulated motion conflicts, as a user would run it. For
/// each sequence (an elevator ride, a laptop covering the view) it renders a EuRoC folder, runs
/// Player -> FrontendComponent -> BackendComponent (MC-VIO mode) over DDS while a Recorder writes
/// the bus to an MCAP bag, runs the same data offline in reference mode, and evaluates both runs
/// against ground truth and the conflict labels.
///
/// Layout of the output folder, per sequence SEQ (elevator, self_occlusion):
///   SEQ/data        the rendered EuRoC folder (images removed at the end unless keep_images)
///   SEQ/bag         rosbag2 MCAP of the run's /imu0, /ground_truth/odometry, /tf*, /mcvio/* topics
///   SEQ/mcvio       trajectory.tum and secondary.tum from the last /mcvio/path and
///                   /mcvio/secondary_path (final: conflict windows revised), trajectory_online.tum
///                   and secondary_online.tum from /mcvio/odometry and /mcvio/secondary_odometry (per
///                   frame), conflict.csv from /mcvio/conflict (columns as `mcvio run` writes)
///   SEQ/reference   `mcvio run --mode reference` output
///   SEQ/report      eval.json, eval.md and the PNG figures of `mcvio eval`
class DemoPipeline {
 public:
  struct Options {
    std::string out_dir = "/tmp/mcvio_demo";
    /// Conflict handling of the DDS backend: imu, selective or auto (reference is the baseline).
    std::string mode = "auto";
    /// Length of each simulated sequence [s]; the conflict covers 10/30 .. 22/30 of it.
    double duration_s = 30.0;
    bool keep_images = false;  ///< keep SEQ/data/mav0/cam*/data so a rerun skips rendering
    std::uint64_t seed = 3;
    dds::ParticipantOptions participant;  ///< domain and profiles of the components' participants
    std::vector<std::string> scenarios = {"elevator", "self_occlusion"};

    /// Throws std::invalid_argument naming the option.
    void validate() const;
  };

  /// What one sequence gave; errors are NaN when a run has no poses to evaluate.
  struct SequenceResult {
    std::string name;
    std::size_t frames = 0, reference_poses = 0, mcvio_poses = 0;
    double reference_ate_m = 0, mcvio_ate_m = 0;          ///< ATE RMSE after position+yaw alignment
    double mcvio_online_ate_m = 0;  ///< the same for MC-VIO's per-frame output (before the conflict window's revision)
    double reference_rpe_m = 0, mcvio_rpe_m = 0;          ///< RPE RMSE over 1 s
    double mcvio_tpr = 0, mcvio_fpr = 0;                  ///< per-frame detection against the labels
    bool has_detection = false;
    /// Against the conflict intervals in hindsight (NaN when the log has none).
    double mcvio_hindsight_tpr = std::numeric_limits<double>::quiet_NaN();
    double mcvio_hindsight_fpr = std::numeric_limits<double>::quiet_NaN();
    /// Seconds from the first labelled frame to MC-VIO's first detection (NaN: never, or no labels).
    double mcvio_onset_delay_s = std::numeric_limits<double>::quiet_NaN();
    /// Rides (elevator): how far the labelled interval carried the device up, how far each
    /// trajectory says it went, and how far the conflicting frame (the cabin) moved.
    evaluation::RideMeasurement reference_ride, mcvio_ride;
    bool rendered = false;                                ///< false: reused from a previous run
    double render_s = 0, dds_s = 0, reference_s = 0;      ///< wall time of each step
    std::string report_dir, bag_dir;
    std::vector<std::string> plots;
    std::size_t bag_messages = 0;
    double reduction() const;  ///< 100 * (reference - mcvio) / reference ATE
  };

  explicit DemoPipeline(Options options);
  /// Runs every sequence; prints one line per step to stdout (progress bars on a terminal).
  /// Throws mcvio::InputError or std::runtime_error with what failed.
  std::vector<SequenceResult> run() const;
  /// The final table and the paths of reports, plots and bags.
  static std::string summary(const std::vector<SequenceResult>& results, const std::string& mode);

 private:
  struct Sequence;
  /// Throws std::runtime_error if another process already publishes the demo's input or output
  /// topics on the domain (they would mix into the run).
  void checkDomainIsFree() const;
  Sequence plan(const std::string& scenario) const;
  bool render(const Sequence& s) const;
  void runOverDds(const Sequence& s, SequenceResult& r) const;
  void runReference(const Sequence& s) const;
  void evaluate(const Sequence& s, SequenceResult& r) const;

  Options options_;
};

}  // namespace mcvio::cli
