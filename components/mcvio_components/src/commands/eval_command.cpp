#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "commands/command_context.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/evaluation/evaluator.hpp"
#include "mcvio/evaluation/report_plotter.hpp"
#include "mcvio/evaluation/report_writer.hpp"
#include "mcvio/evaluation/trajectory_io.hpp"

namespace mcvio::cli {

namespace {

namespace fs = std::filesystem;
namespace ev = mcvio::evaluation;

// `mcvio run` marks a run it could not finish; its trajectory stops where the error struck.
void warnIfIncomplete(const fs::path& stats_path) {
  if (!fs::is_regular_file(stats_path)) return;
  try {
    const auto stats = nlohmann::json::parse(std::ifstream(stats_path));
    if (stats.value("completed", true)) return;
    std::cerr << "mcvio eval: warning: " << stats_path.string() << ": this run did not complete ("
              << stats.value("error", std::string("no reason recorded")) << "); its trajectory ends where it stopped\n";
  } catch (const nlohmann::json::exception& e) {
    std::cerr << "mcvio eval: warning: " << stats_path.string() << ": not readable JSON (" << e.what() << ")\n";
  }
}

/// "NAME=PATH" or just PATH (named after its folder or file stem). A folder is an `mcvio run`
/// output: OUT/trajectory.tum and, when present, OUT/trajectory_online.tum and OUT/conflict.csv.
ev::EstimateInput loadEstimate(const std::string& spec) {
  const auto eq = spec.find('=');
  std::string name = eq == std::string::npos ? std::string() : spec.substr(0, eq);
  const std::string path = eq == std::string::npos ? spec : spec.substr(eq + 1);
  if (path.empty()) throw InputError("--est '" + spec + "': no path after '='");
  const fs::path p(path);
  if (name.empty()) name = fs::is_directory(p) ? p.lexically_normal().filename().string() : p.stem().string();
  if (name.empty() || name == ".") name = fs::absolute(p).lexically_normal().parent_path().filename().string();
  ev::EstimateInput input;
  input.name = name;
  if (fs::is_directory(p)) {
    if (!fs::is_regular_file(p / "trajectory.tum")) {
      throw InputError(path + ": no trajectory.tum in this folder (expected the output folder of `mcvio run`)");
    }
    input.trajectory = ev::loadTum((p / "trajectory.tum").string());
    input.online_trajectory = ev::loadOnlineTrajectory(path);
    if (fs::is_regular_file(p / "conflict.csv")) input.detector = ev::DetectorLog::load((p / "conflict.csv").string());
    warnIfIncomplete(p / "stats.json");
  } else if (fs::exists(p)) {
    input.trajectory = ev::loadTum(path);
  } else {
    throw InputError(path + ": no such file or folder (--est " + spec + ")");
  }
  return input;
}

}  // namespace

void addEvalCommand(CLI::App& app, CommandContext&) {
  struct Options {
    std::string gt, labels, out, baseline, config, association;
    std::vector<std::string> estimates;
    double rpe_delta_s = 1.0, rpe_delta_m = 1.0;
    bool suspected_positive = false, no_plots = false, quiet = false;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "eval",
      "Evaluate one or more runs of a sequence against its ground truth: ATE RMSE/mean/median/max after\n"
      "SE(3) and after position+yaw alignment (position+yaw also for the per-frame output,\n"
      "OUT/trajectory_online.tum, where a run revised its trajectory), ATE inside and outside labelled\n"
      "conflict intervals, RPE over a fixed time and a fixed travelled distance, and, for runs with\n"
      "OUT/conflict.csv, the detector's per-frame TPR/FPR and ROC/AUC (chi2 ratio, inconsistent fraction,\n"
      "evidence score) against mav0/conflict_labels.csv (online, and against the run's conflict intervals\n"
      "in hindsight when conflict.csv has interval_onset_ns/interval_end_ns), and per labelled interval how\n"
      "late the detector came on (onset delay) and how long it stayed on after the interval ended (release\n"
      "lag). Runs are compared with a baseline run (relative reduction of each error, positive = less\n"
      "error). Writes REPORT/eval.json, REPORT/eval.md (also printed), trajectory_top.png,\n"
      "trajectory_side.png, error_over_time.png, roc.png (with detector logs), evidence_over_time.png (with\n"
      "an evidence_score column), ground_truth.tum and <run>_aligned_se3.tum.\n"
      "Examples:\n"
      "  mcvio eval --gt ../shared/data/euroc_V1_01_excerpt --est /tmp/run --out /tmp/report\n"
      "  mcvio eval --gt /tmp/elevator --est reference=/tmp/run_ref --est mcvio=/tmp/run_mc \\\n"
      "             --baseline reference --out /tmp/report_elevator\n"
      "  mcvio eval --gt gt.tum --est okvis=okvis.tum --est mcvio=/tmp/run --labels labels.csv \\\n"
      "             --rpe-delta-s 2 --rpe-delta-m 5 --out /tmp/report_cmp");
  cmd->add_option("--gt", opt->gt,
                  "ground truth: a EuRoC folder (holding mav0/, uses mav0/state_groundtruth_estimate0/data.csv),\n"
                  "that CSV itself, or a TUM file (t x y z qx qy qz qw, t in s)")
      ->required();
  cmd->add_option("--est", opt->estimates,
                  "a run as NAME=PATH (repeatable; NAME defaults to the folder or file name). PATH is an\n"
                  "`mcvio run` output folder (OUT/trajectory.tum, plus OUT/trajectory_online.tum and OUT/conflict.csv if "
                  "present) or a TUM file")
      ->required();
  cmd->add_option("--labels", opt->labels,
                  "conflict labels CSV (#timestamp [ns],in_conflict,motion,covered_fraction) or a EuRoC folder;\n"
                  "default: mav0/conflict_labels.csv of --gt when it is a EuRoC folder that has one");
  cmd->add_option("--out", opt->out, "report folder (created; files in it are replaced)")->required();
  cmd->add_option("--baseline", opt->baseline, "NAME of the run the others are compared with (default: the first --est)");
  cmd->add_option("--rpe-delta-s", opt->rpe_delta_s, "RPE over this time [s]")->capture_default_str();
  cmd->add_option("--rpe-delta-m", opt->rpe_delta_m, "RPE over this ground-truth path length [m]")->capture_default_str();
  cmd->add_option("--association", opt->association,
                  "how estimate poses find ground truth: interpolate (ground truth interpolated at estimate\n"
                  "times, default) or nearest (nearest pose within 20 ms)")
      ->check(CLI::IsMember({"interpolate", "nearest"}));
  cmd->add_flag("--suspected-positive", opt->suspected_positive,
                "count detector frames in state `suspected` as detections too (default: only `conflict`)");
  cmd->add_option("--config", opt->config,
                  "YAML with evaluation options (rpe_delta_s, rpe_delta_m, rpe_tolerance, baseline,\n"
                  "association: {method, max_interpolation_gap_s, max_time_difference_s},\n"
                  "alignment: {min_position_spread_m}: below this ground-truth spread the rotation comes from orientations,\n"
                  "detection: {label_tolerance_s, suspected_is_positive}), e.g. config/eval.yaml (the defaults);\n"
                  "flags given here override it");
  cmd->add_flag("--no-plots", opt->no_plots, "skip the PNG figures");
  cmd->add_flag("-q,--quiet", opt->quiet, "do not print the Markdown table");
  cmd->callback([opt, cmd] {
    ev::EvaluationOptions o = opt->config.empty() ? ev::EvaluationOptions{} : ev::EvaluationOptions::fromYamlFile(opt->config);
    if (cmd->count("--rpe-delta-s")) o.rpe_delta_s = opt->rpe_delta_s;
    if (cmd->count("--rpe-delta-m")) o.rpe_delta_m = opt->rpe_delta_m;
    if (cmd->count("--baseline")) o.baseline = opt->baseline;
    if (!opt->association.empty()) {
      o.association.method = opt->association == "nearest" ? ev::AssociationOptions::Method::kNearest
                                                           : ev::AssociationOptions::Method::kInterpolate;
    }
    if (opt->suspected_positive) o.detection.suspected_is_positive = true;
    o.validate();
    // A folder that cannot be written should say so now, not after every run was read.
    try {
      fs::create_directories(opt->out);
    } catch (const fs::filesystem_error& e) {
      throw InputError("--out " + opt->out + ": cannot create the report folder (" + e.code().message() + ")");
    }
    if (!fs::is_directory(opt->out)) throw InputError("--out " + opt->out + ": exists and is not a folder");

    const ev::Trajectory gt = ev::loadTrajectory(opt->gt);
    std::optional<ev::ConflictLabelTimeline> labels;
    if (!opt->labels.empty()) {
      labels = ev::ConflictLabelTimeline::load(opt->labels);
    } else if (fs::is_directory(opt->gt)) {
      const fs::path g(opt->gt);
      for (const fs::path& candidate : {g / "mav0" / "conflict_labels.csv", g / "conflict_labels.csv"}) {
        if (fs::is_regular_file(candidate)) {
          labels = ev::ConflictLabelTimeline::load(candidate.string());
          break;
        }
      }
    }
    std::vector<ev::EstimateInput> runs;
    for (const auto& spec : opt->estimates) runs.push_back(loadEstimate(spec));

    const ev::EvaluationReport report = ev::Evaluator(o).evaluate(gt, runs, labels);
    ev::ReportWriter::write(report, opt->out);
    std::vector<std::string> written = {opt->out + "/eval.json", opt->out + "/eval.md"};
    if (!opt->no_plots) {
      for (const auto& f : ev::ReportPlotter::write(report, opt->out)) written.push_back(f);
    }
    if (!opt->quiet) std::cout << ev::ReportWriter::toMarkdown(report);
    for (const auto& e : report.estimates) {
      // An alignment fitted to a pose or two fits it exactly: an ATE of zero says nothing.
      if (e.ate_se3.translation.count < 3) {
        std::cerr << "mcvio eval: warning: " << e.name << ": only " << e.ate_se3.translation.count
                  << " pose(s) matched the ground truth; the aligned ATE of fewer than 3 poses is meaningless\n";
      } else if (!std::isfinite(e.ate_se3.translation.rmse) || !std::isfinite(e.ate_posyaw.translation.rmse)) {
        std::cerr << "mcvio eval: warning: " << e.name
                  << ": the ATE is not finite (positions too large to align, e.g. a diverged run)\n";
      }
      if (e.ate_se3.unmatched > 0) {
        std::cerr << "mcvio eval: warning: " << e.name << ": " << e.ate_se3.unmatched << " of " << e.poses
                  << " poses have no ground truth (outside its time span or in a gap) and are not evaluated\n";
      }
      if (e.detection && e.detection->labels_without_row > 0) {
        std::cerr << "mcvio eval: note: " << e.name << ": " << e.detection->labels_without_row
                  << " labelled frames have no detector row (frames the run skipped)\n";
      }
      if (!e.detector_source.empty() && !labels) {
        std::cerr << "mcvio eval: note: " << e.name << " has " << e.detector_source
                  << " but there are no conflict labels (--labels): no detection metrics\n";
      }
    }
    std::cerr << "mcvio eval: " << report.estimates.size() << " run(s) against " << report.ground_truth_source << " -> ";
    for (std::size_t i = 0; i < written.size(); ++i) std::cerr << (i ? ", " : "") << written[i];
    std::cerr << "\n";
  });
}

}  // namespace mcvio::cli
