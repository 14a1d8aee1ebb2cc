#include "mcvio/evaluation/benchmark_report_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/write_failure.hpp"
#include "mcvio/evaluation/plot_canvas.hpp"

namespace mcvio::evaluation {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json check(const std::optional<bool>& c) { return c ? json(*c) : json(nullptr); }

std::string fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

/// Compact but never exponential: 1542, 80.54, 0.749, 0.018.
std::string figure(double v) {
  const double a = std::abs(v);
  return fmt(a >= 100 ? "%.0f" : a >= 1 ? "%.2f" : "%.3f", v);
}

std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

std::string checksText(const BenchmarkRun& r) {
  const std::pair<const char*, const std::optional<bool>*> items[] = {
      {"ATE", &r.checks.ate_reduction}, {"RPE", &r.checks.rpe_reduction},     {"clean", &r.checks.clean_ate},
      {"det", &r.checks.detection},     {"ride", &r.checks.ride_displacement}, {"cabin", &r.checks.secondary_motion},
      {"vehicle", &r.checks.vehicle_motion}, {"cost", &r.checks.cost}};
  std::vector<std::string> parts;
  for (const auto& [name, c] : items)
    if (c->has_value()) parts.push_back(std::string(name) + (**c ? " ok" : " FAIL"));
  return parts.empty() ? "-" : join(parts);
}

/// Distinct BGR colours per mode, in the modes' order.
cv::Scalar modeColor(std::size_t i) {
  static const cv::Scalar colors[] = {{60, 60, 60},   {40, 40, 220}, {200, 120, 30},
                                      {40, 160, 40},  {160, 40, 160}, {0, 140, 230}};
  return colors[i % (sizeof colors / sizeof colors[0])];
}

/// Mean over seeds of `value` per scenario (rows) and mode (columns); NaN where nothing measured.
std::vector<std::vector<double>> perScenarioMeans(const BenchmarkResult& result,
                                                  const std::vector<std::string>& scenarios,
                                                  double (*value)(const BenchmarkRun&)) {
  std::vector<std::vector<double>> m(scenarios.size(), std::vector<double>(result.options.modes.size(), NAN));
  for (std::size_t s = 0; s < scenarios.size(); ++s) {
    for (std::size_t k = 0; k < result.options.modes.size(); ++k) {
      double sum = 0;
      int n = 0;
      for (const auto& sr : result.sequences) {
        if (sr.sequence.sweep || sr.sequence.scenario != scenarios[s]) continue;
        const BenchmarkRun* r = sr.find(result.options.modes[k]);
        if (r && std::isfinite(value(*r))) {
          sum += value(*r);
          ++n;
        }
      }
      if (n) m[s][k] = sum / n;
    }
  }
  return m;
}

/// A grouped bar chart (groups = scenarios, bars = modes) with the value above each bar.
void writeBarChart(const std::string& path, const std::string& title, const std::string& y_label,
                   const std::vector<std::string>& groups, const std::vector<std::string>& series,
                   const std::vector<std::vector<double>>& values) {
  const int W = 1000, H = 700, left = 90, right = 30, top = 60, bottom = 140;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double vmax = 0;
  for (const auto& row : values)
    for (double v : row)
      if (std::isfinite(v)) vmax = std::max(vmax, v);
  if (vmax <= 0) vmax = 1;
  const auto ticks = PlotCanvas::niceTicks(0, vmax * 1.1, 6);
  const double ymax = std::max(vmax * 1.1, ticks.empty() ? vmax : ticks.back());
  const int plot_w = W - left - right, plot_h = H - top - bottom;
  auto yPix = [&](double v) { return top + plot_h - int(std::lround(v / ymax * plot_h)); };
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  cv::putText(img, title, {left, 35}, font, 0.7, {30, 30, 30}, 2, cv::LINE_AA);
  for (double t : ticks) {
    if (t > ymax) continue;
    cv::line(img, {left, yPix(t)}, {W - right, yPix(t)}, {225, 225, 225}, 1);
    cv::putText(img, fmt("%g", t == 0 ? 0.0 : t), {10, yPix(t) + 5}, font, 0.45, {40, 40, 40}, 1, cv::LINE_AA);
  }
  cv::line(img, {left, top}, {left, top + plot_h}, {40, 40, 40}, 1);
  cv::line(img, {left, top + plot_h}, {W - right, top + plot_h}, {40, 40, 40}, 1);
  cv::putText(img, y_label, {10, top - 12}, font, 0.5, {40, 40, 40}, 1, cv::LINE_AA);
  const double group_w = double(plot_w) / std::max<std::size_t>(1, groups.size());
  const double bar_w = group_w * 0.8 / std::max<std::size_t>(1, series.size());
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const double gx = left + g * group_w + group_w * 0.1;
    for (std::size_t s = 0; s < series.size(); ++s) {
      const double v = values[g][s];
      const int x0 = int(gx + s * bar_w), x1 = int(gx + (s + 1) * bar_w) - 2;
      if (!std::isfinite(v)) {
        cv::putText(img, "n/a", {x0, top + plot_h - 6}, font, 0.35, {90, 90, 90}, 1, cv::LINE_AA);
        continue;
      }
      cv::rectangle(img, {x0, yPix(v)}, {x1, top + plot_h}, modeColor(s), cv::FILLED);
      cv::putText(img, fmt(v < 10 ? "%.2f" : "%.0f", v), {x0, yPix(v) - 4}, font, 0.33, {30, 30, 30}, 1, cv::LINE_AA);
    }
    int baseline = 0;
    const cv::Size ts = cv::getTextSize(groups[g], font, 0.5, 1, &baseline);
    cv::putText(img, groups[g], {int(left + (g + 0.5) * group_w) - ts.width / 2, top + plot_h + 25}, font, 0.5,
                {30, 30, 30}, 1, cv::LINE_AA);
  }
  for (std::size_t s = 0; s < series.size(); ++s) {
    const int x = left + int(s) * 180, y = H - 50;
    cv::rectangle(img, {x, y - 12}, {x + 24, y + 4}, modeColor(s), cv::FILLED);
    cv::putText(img, series[s], {x + 32, y + 2}, font, 0.5, {30, 30, 30}, 1, cv::LINE_AA);
  }
  if (!cv::imwrite(path, img)) throwCannotWrite(path, errno, "the figure");
}

}  // namespace

std::string BenchmarkReportWriter::toJson(const BenchmarkResult& result) {
  const auto& o = result.options;
  json j;
  j["level"] = result.level;
  j["wall_s"] = result.wall_s;
  j["options"] = {{"modes", o.modes},
                  {"scenarios", o.scenarios},
                  {"seeds", o.seeds},
                  {"sequence_duration_s", o.sequence_duration_s},
                  {"onset_s", o.onset_s},
                  {"conflict_duration_s", o.conflict_duration_s},
                  {"sweep_durations_s", o.sweep_durations_s},
                  {"sweep_scenarios", o.sweep_scenarios},
                  {"sweep_tail_s", o.sweep_tail_s},
                  {"oracle_track_labels", o.oracle_track_labels},
                  {"rpe_delta_s", o.rpe_delta_s},
                  {"pixel_noise_sigma", o.features.pixel_noise_sigma},
                  {"targets",
                   {{"conflict_ate_reduction_percent", o.targets.conflict_ate_reduction_percent},
                    {"conflict_rpe_reduction_percent", o.targets.conflict_rpe_reduction_percent},
                    {"clean_max_ate_increase_percent", o.targets.clean_max_ate_increase_percent},
                    {"min_tpr", o.targets.min_tpr},
                    {"max_fpr", o.targets.max_fpr},
                    {"ride_displacement_tolerance_percent", o.targets.ride_displacement_tolerance_percent},
                    {"secondary_motion_tolerance_percent", o.targets.secondary_motion_tolerance_percent},
                    {"max_added_cost_percent", o.targets.max_added_cost_percent}}}};
  if (result.level == "images") {
    j["options"]["render_rig"] = result.render_rig.empty() ? "EuRoC V1_01" : result.render_rig;
    j["options"]["texture_filter"] = result.texture_filter;
  }
  json targets = json::array();
  for (const auto& t : result.targets)
    targets.push_back({{"target", t.target}, {"mode", t.mode}, {"passed", t.passed}, {"total", t.total},
                       {"pass", t.pass()}, {"worst", number(t.worst)}, {"worst_sequence", t.worst_sequence}});
  j["targets"] = targets;
  json sequences = json::array();
  for (const auto& sr : result.sequences) {
    const auto& s = sr.sequence;
    json runs = json::array();
    for (const auto& r : sr.runs) {
      runs.push_back({{"mode", r.mode},
                      {"frames", r.frames},
                      {"tracked_frames", r.tracked_frames},
                      {"resets", r.resets},
                      {"wall_s", r.wall_s},
                      {"ate_posyaw_rmse_m", number(r.ate_posyaw_m)},
                      {"ate_posyaw_online_rmse_m", number(r.ate_posyaw_online_m)},
                      {"ate_se3_rmse_m", number(r.ate_se3_m)},
                      {"ate_posyaw_in_conflict_rmse_m", number(r.ate_posyaw_in_conflict_m)},
                      {"rpe_translation_rmse_m", number(r.rpe_translation_m)},
                      {"rpe_rotation_rmse_deg", number(r.rpe_rotation_deg)},
                      {"detection",
                       {{"tp", r.tp}, {"fp", r.fp}, {"tn", r.tn}, {"fn", r.fn},
                        {"tpr", number(r.tpr)}, {"fpr", number(r.fpr)},
                        {"hindsight_tpr", number(r.hindsight_tpr)}, {"hindsight_fpr", number(r.hindsight_fpr)},
                        {"onset_delay_s", number(r.onset_delay_s)}, {"release_lag_s", number(r.release_lag_s)},
                        {"roc_best_tpr_at_max_fpr", number(r.roc_best_tpr)}, {"roc_best_score", r.roc_best_score},
                        {"auc_propagated_chi2_ratio", number(r.auc_propagated)},
                        {"auc_inconsistent_fraction", number(r.auc_fraction)},
                        {"auc_evidence_score", number(r.auc_evidence)}}},
                      {"cpu_median_ms", number(r.cpu_median_ms)},
                      {"cpu_mean_ms", number(r.cpu_mean_ms)},
                      {"conflict_stage_mean_ms", number(r.conflict_mean_ms)},
                      {"ride",
                       {{"truth_dz_m", number(r.ride_truth_dz_m)}, {"estimate_dz_m", number(r.ride_estimate_dz_m)},
                        {"error_percent", number(r.ride_error_percent)}, {"secondary_dz_m", number(r.secondary_dz_m)},
                        {"secondary_error_percent", number(r.secondary_error_percent)}}},
                      {"travel",
                       {{"truth_m", number(r.travel_truth_m)}, {"secondary_m", number(r.secondary_travel_m)},
                        {"secondary_error_percent", number(r.secondary_travel_error_percent)}}},
                      {"vs_reference",
                       {{"ate_reduction_percent", number(r.ate_reduction_percent)},
                        {"ate_in_conflict_reduction_percent", number(r.ate_in_conflict_reduction_percent)},
                        {"rpe_reduction_percent", number(r.rpe_reduction_percent)},
                        {"added_cost_percent", number(r.added_cost_percent)}}},
                      {"checks",
                       {{"ate_reduction", check(r.checks.ate_reduction)},
                        {"rpe_reduction", check(r.checks.rpe_reduction)},
                        {"clean_ate", check(r.checks.clean_ate)},
                        {"detection", check(r.checks.detection)},
                        {"ride_displacement", check(r.checks.ride_displacement)},
                        {"secondary_motion", check(r.checks.secondary_motion)},
                        {"vehicle_motion", check(r.checks.vehicle_motion)},
                        {"cost", check(r.checks.cost)},
                        {"all_pass", r.checks.allPass()}}}});
    }
    sequences.push_back({{"name", s.name},
                         {"scenario", s.scenario},
                         {"seed", s.seed},
                         {"duration_s", s.duration_s},
                         {"onset_s", s.onset_s},
                         {"conflict_duration_s", s.conflict_duration_s},
                         {"travel_m", s.travel_m},
                         {"sweep", s.sweep},
                         {"frames", sr.frames},
                         {"conflict_frames", sr.conflict_frames},
                         {"simulate_s", sr.simulate_s},
                         {"clean_floor_ate_posyaw_m", number(sr.clean_floor_ate_m)},
                         {"runs", runs}});
  }
  j["sequences"] = sequences;
  return j.dump(2) + "\n";
}

std::string BenchmarkReportWriter::toMarkdown(const BenchmarkResult& result) {
  const auto& o = result.options;
  std::ostringstream md;
  std::vector<std::string> seeds;
  for (auto s : o.seeds) seeds.push_back(std::to_string(s));
  std::vector<std::string> sweep;
  for (double d : o.sweep_durations_s) sweep.push_back(fmt("%g", d));
  md << "# MC-VIO benchmark (" << (result.level == "images" ? "image" : "feature") << " level)\n\n";
  if (result.level == "images")
    md << "Rendered stereo images (mcvio_sim; overlay_semi_real: rendered along a recorded trajectory with its real IMU, "
          "overlay injected) and recorded sequences (real_*) -> the whole offline pipeline (frontend + estimator) per mode. "
          "Rendered with the rig of "
       << (result.render_rig.empty() ? std::string("EuRoC V1_01") : "`" + result.render_rig + "`") << ", "
       << result.texture_filter << " texture filter.";
  else
    md << "FeatureSimulator tracks (pixel noise " << fmt("%g", o.features.pixel_noise_sigma) << " px, track labels "
       << (o.oracle_track_labels ? "from the ground truth (oracle)" : "cleared: no oracle") << ") -> SlidingWindowEstimator"
       << " per mode.";
  md << " Scenarios: " << (o.scenarios.empty() ? std::string("(none)") : join(o.scenarios)) << "; seeds " << join(seeds) << "; " << fmt("%g", o.sequence_duration_s)
     << " s sequences, conflict " << fmt("%g", o.conflict_duration_s) << " s from " << fmt("%g", o.onset_s) << " s. Modes: "
     << join(o.modes) << ".";
  if (!o.sweep_durations_s.empty())
    md << " Duration sweep: " << join(o.sweep_scenarios) << " at " << join(sweep) << " s (seed " << o.seeds.front() << ").";
  md << " Wall time " << fmt("%.0f", result.wall_s) << " s.\n\n"
     << "ATE: position RMSE after position+yaw (and SE(3)) alignment, of the final trajectory (the conflict window "
        "revises an IMU-dominated interval once it ends); ATE per-frame output: the same for the estimates as each frame "
        "published them; RPE: translation RMSE over " << fmt("%g", o.rpe_delta_s)
     << " s pairs; reductions: 100 (reference - mode) / reference on the same sequence; detection: per frame, `conflict` "
     << "state vs labels; added cost: mean backend CPU per frame above the reference's minus its conflict stage.\n\n";

  md << "## Targets\n\n| Target | Mode | Runs passing | Worst | Worst sequence | Result |\n|---|---|---|---|---|---|\n";
  for (const auto& t : result.targets)
    md << "| " << t.target << " | " << t.mode << " | " << t.passed << "/" << t.total << " | " << figure(t.worst)
       << " | " << t.worst_sequence << " | " << (t.pass() ? "pass" : "FAIL") << " |\n";
  md << "\n";

  md << "## Scenarios\n\n"
     << "| Sequence | Mode | Tracked | ATE pos+yaw [m] | ATE per-frame output [m] | ATE SE(3) [m] | ATE in conflict [m] | RPE [m] | ATE red. [%] | "
        "RPE red. [%] | TPR | FPR | TPR / FPR in hindsight | ROC TPR@FPR<=" << fmt("%g", o.targets.max_fpr)
     << " | CPU median [ms] | Added cost [%] | Checks |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& sr : result.sequences) {
    if (sr.sequence.sweep) continue;
    for (const auto& r : sr.runs) {
      const bool ref = r.mode == "reference";
      md << "| " << sr.sequence.name << " | " << r.mode << " | " << r.tracked_frames << "/" << r.frames << " | "
         << fmt("%.3f", r.ate_posyaw_m) << " | " << fmt("%.3f", r.ate_posyaw_online_m) << " | " << fmt("%.3f", r.ate_se3_m)
         << " | " << fmt("%.3f", r.ate_posyaw_in_conflict_m)
         << " | " << fmt("%.4f", r.rpe_translation_m) << " | " << (ref ? "-" : fmt("%+.1f", r.ate_reduction_percent)) << " | "
         << (ref ? "-" : fmt("%+.1f", r.rpe_reduction_percent)) << " | " << fmt("%.3f", r.tpr) << " | " << fmt("%.4f", r.fpr)
         << " | " << fmt("%.3f", r.hindsight_tpr) << " / " << fmt("%.4f", r.hindsight_fpr) << " | " << fmt("%.3f", r.roc_best_tpr) << " | " << fmt("%.2f", r.cpu_median_ms) << " | "
         << fmt("%+.1f", r.added_cost_percent) << " | " << checksText(r) << " |\n";
    }
  }
  md << "\n";

  bool timing_header = false;
  for (const auto& sr : result.sequences) {
    if (sr.sequence.sweep || !sr.sequence.hasConflict()) continue;
    for (const auto& r : sr.runs) {
      if (!timing_header) {
        md << "## Detection timing (the labelled span)\n\n"
           << "Onset delay: from the first labelled frame to the first detected one. Release lag: from the last "
              "labelled frame to the end of the last detection (negative: it let go before the motion ended). A TPR of "
           << fmt("%g", o.targets.min_tpr) << " leaves " << fmt("%g", 100.0 * (1.0 - o.targets.min_tpr))
           << " % of the labelled frames to miss, onset and end together (the last column); each frame of positive "
              "release lag is a false positive.\n\n"
           << "| Sequence | Mode | TPR | Onset delay [s] | Release lag [s] | FPR | Misses a TPR of " << fmt("%g", o.targets.min_tpr)
           << " allows [s] |\n|---|---|---|---|---|---|---|\n";
        timing_header = true;
      }
      md << "| " << sr.sequence.name << " | " << r.mode << " | " << fmt("%.3f", r.tpr) << " | " << fmt("%.2f", r.onset_delay_s)
         << " | " << fmt("%+.2f", r.release_lag_s) << " | " << fmt("%.4f", r.fpr) << " | "
         << fmt("%.2f", (1.0 - o.targets.min_tpr) * sr.sequence.conflict_duration_s) << " |\n";
    }
  }
  if (timing_header) md << "\n";

  bool ride_header = false;
  for (const auto& sr : result.sequences) {
    if (sr.sequence.sweep || sr.sequence.scenario != "elevator") continue;
    for (const auto& r : sr.runs) {
      if (!std::isfinite(r.ride_truth_dz_m)) continue;
      if (!ride_header) {
        md << "## Elevator ride (vertical displacement over the labelled interval)\n\n"
           << "| Sequence | Mode | Truth [m] | Estimate [m] | Error [%] | Secondary frame z [m] | Secondary error [%] |\n"
           << "|---|---|---|---|---|---|---|\n";
        ride_header = true;
      }
      md << "| " << sr.sequence.name << " | " << r.mode << " | " << fmt("%.3f", r.ride_truth_dz_m) << " | "
         << fmt("%.3f", r.ride_estimate_dz_m) << " | " << fmt("%.1f", r.ride_error_percent) << " | "
         << fmt("%.3f", r.secondary_dz_m) << " | " << fmt("%.1f", r.secondary_error_percent) << " |\n";
    }
  }
  if (ride_header) md << "\n";

  bool travel_header = false;
  for (const auto& sr : result.sequences) {
    if (sr.sequence.sweep || sr.sequence.scenario != "vehicle") continue;
    for (const auto& r : sr.runs) {
      if (!std::isfinite(r.secondary_travel_error_percent)) continue;
      if (!travel_header) {
        md << "## Vehicle travel (the secondary frame's translation over the labelled interval, in the ground "
              "truth's frame by the position+yaw alignment)\n\n"
           << "| Sequence | Mode | Truth [m] | Secondary frame [m] | Error [%] |\n|---|---|---|---|---|\n";
        travel_header = true;
      }
      md << "| " << sr.sequence.name << " | " << r.mode << " | " << fmt("%.3f", r.travel_truth_m) << " | "
         << fmt("%.3f", r.secondary_travel_m) << " | " << fmt("%.1f", r.secondary_travel_error_percent) << " |\n";
    }
  }
  if (travel_header) md << "\n";

  bool floor_header = false;
  for (const auto& sr : result.sequences) {
    const BenchmarkRun* ref = sr.find("reference");
    if (!std::isfinite(sr.clean_floor_ate_m) || ref == nullptr || !std::isfinite(ref->ate_posyaw_m)) continue;
    if (!floor_header) {
      md << "## Clean floor (reference on the same sequence without the conflict)\n\n"
         << "No method gets below the VIO's own error on the clean sequence: the largest reachable ATE reduction is "
            "100 (reference - floor) / reference. Excess removed: 100 (reference - mode) / (reference - floor).\n\n"
         << "| Sequence | Clean floor ATE pos+yaw [m] | Reference [m] | Largest reachable reduction [%] | Mode | ATE [m] | "
            "Excess removed [%] |\n|---|---|---|---|---|---|---|\n";
      floor_header = true;
    }
    const double excess = ref->ate_posyaw_m - sr.clean_floor_ate_m;
    for (const auto& r : sr.runs) {
      if (r.mode == "reference") continue;
      md << "| " << sr.sequence.name << " | " << fmt("%.3f", sr.clean_floor_ate_m) << " | " << fmt("%.3f", ref->ate_posyaw_m)
         << " | " << fmt("%.1f", 100.0 * excess / ref->ate_posyaw_m) << " | " << r.mode << " | " << fmt("%.3f", r.ate_posyaw_m)
         << " | " << (excess > 0 ? fmt("%.1f", 100.0 * (ref->ate_posyaw_m - r.ate_posyaw_m) / excess) : "n/a") << " |\n";
    }
  }
  if (floor_header) md << "\n";

  if (!o.sweep_durations_s.empty()) {
    md << "## ATE versus conflict duration (ATE pos+yaw RMSE [m]; in brackets: over the conflict frames)\n\n"
       << "| Scenario | Conflict [s] | Sequence [s] |";
    for (const auto& m : o.modes) md << " " << m << " |";
    md << "\n|---|---|---|";
    for (std::size_t i = 0; i < o.modes.size(); ++i) md << "---|";
    md << "\n";
    for (const auto& sr : result.sequences) {
      if (!sr.sequence.sweep) continue;
      md << "| " << sr.sequence.scenario << " | " << fmt("%g", sr.sequence.conflict_duration_s) << " | "
         << fmt("%g", sr.sequence.duration_s) << " |";
      for (const auto& m : o.modes) {
        const BenchmarkRun* r = sr.find(m);
        md << " " << (r ? fmt("%.3f", r->ate_posyaw_m) : "n/a");
        if (r && std::isfinite(r->ate_posyaw_in_conflict_m)) md << " (" << fmt("%.3f", r->ate_posyaw_in_conflict_m) << ")";
        md << " |";
      }
      md << "\n";
    }
    md << "\n";
  }
  return md.str();
}

std::vector<std::string> BenchmarkReportWriter::writePlots(const BenchmarkResult& result, const std::string& dir) {
  std::vector<std::string> written;
  const auto& modes = result.options.modes;
  std::vector<std::string> scenarios;
  for (const auto& sr : result.sequences)
    if (!sr.sequence.sweep && std::find(scenarios.begin(), scenarios.end(), sr.sequence.scenario) == scenarios.end())
      scenarios.push_back(sr.sequence.scenario);
  if (!scenarios.empty()) {
    const std::string ate = (fs::path(dir) / "ate_by_scenario.png").string();
    writeBarChart(ate, "ATE (position+yaw RMSE) per scenario and mode, mean over seeds", "ATE [m]", scenarios, modes,
                  perScenarioMeans(result, scenarios, [](const BenchmarkRun& r) { return r.ate_posyaw_m; }));
    written.push_back(ate);
    const std::string rpe = (fs::path(dir) / "rpe_by_scenario.png").string();
    writeBarChart(rpe, "RPE (translation RMSE over " + fmt("%g", result.options.rpe_delta_s) + " s) per scenario and mode",
                  "RPE [m]", scenarios, modes,
                  perScenarioMeans(result, scenarios, [](const BenchmarkRun& r) { return r.rpe_translation_m; }));
    written.push_back(rpe);
  }
  for (const auto& scenario : result.options.sweep_scenarios) {
    std::vector<const BenchmarkSequenceResult*> points;
    for (const auto& sr : result.sequences)
      if (sr.sequence.sweep && sr.sequence.scenario == scenario) points.push_back(&sr);
    if (points.empty()) continue;
    std::sort(points.begin(), points.end(), [](auto* a, auto* b) {
      return a->sequence.conflict_duration_s < b->sequence.conflict_duration_s;
    });
    PlotCanvas canvas("ATE versus conflict duration: " + scenario);
    canvas.setXLabel("conflict duration [s]");
    canvas.setYLabel("ATE pos+yaw RMSE [m]");
    bool any = false;
    for (std::size_t k = 0; k < modes.size(); ++k) {
      std::vector<double> x, y;
      for (const auto* sr : points) {
        const BenchmarkRun* r = sr->find(modes[k]);
        if (!r || !std::isfinite(r->ate_posyaw_m)) continue;
        x.push_back(sr->sequence.conflict_duration_s);
        y.push_back(r->ate_posyaw_m);
      }
      if (x.empty()) continue;
      if (x.size() == 1) {  // a single point still shows as a short tick
        x.push_back(x[0] + 0.01);
        y.push_back(y[0]);
      }
      canvas.addLine(x, y, modeColor(k), modes[k], 2);
      any = true;
    }
    if (!any) continue;
    const std::string path = (fs::path(dir) / ("ate_vs_duration_" + scenario + ".png")).string();
    canvas.save(path);
    written.push_back(path);
  }
  return written;
}

std::vector<std::string> BenchmarkReportWriter::write(const BenchmarkResult& result, const std::string& dir, bool plots) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the report folder: " + ec.message());
  std::vector<std::string> written;
  auto put = [&](const std::string& name, const std::string& text) {
    const std::string path = (fs::path(dir) / name).string();
    std::ofstream f(path);
    f << text;
    f.flush();
    if (!f) throwCannotWrite(path, errno);
    written.push_back(path);
  };
  put("bench.json", toJson(result));
  put("bench.md", toMarkdown(result));
  if (plots) {
    const auto figures = writePlots(result, dir);
    written.insert(written.end(), figures.begin(), figures.end());
  }
  return written;
}

}  // namespace mcvio::evaluation
