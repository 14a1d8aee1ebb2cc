#include "mcvio/evaluation/report_writer.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/write_failure.hpp"
#include "mcvio/evaluation/trajectory_io.hpp"

namespace mcvio::evaluation {

namespace {

using nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// NaN and infinities become null: JSON has no such numbers.
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json asJson(const ErrorStatistics& s) {
  return {{"count", s.count},         {"rmse", number(s.rmse)}, {"mean", number(s.mean)},
          {"median", number(s.median)}, {"std", number(s.std)},   {"min", number(s.min)},
          {"max", number(s.max)}};
}

json asJson(const Eigen::Isometry3d& T) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) {
    json row = json::array();
    for (int c = 0; c < 4; ++c) row.push_back(T.matrix()(r, c));
    rows.push_back(row);
  }
  return rows;
}

json asJson(const AteResult& a) {
  return {{"alignment", toString(a.alignment)},
          {"rotation_from", a.rotation_from_orientations ? "orientations" : "positions"},
          {"ground_truth_position_spread_m", a.position_spread_m},
          {"matched", a.translation_errors.size()},
          {"unmatched", a.unmatched},
          {"translation_m", asJson(a.translation)},
          {"rotation_deg", asJson(a.rotation)},
          {"T_gt_est", asJson(a.T_gt_est)}};
}

json asJson(const RpeResult& r) {
  json j = {{"pairs", r.translation_errors.size()},
            {"tolerance", r.options.tolerance},
            {"translation_m", asJson(r.translation)},
            {"rotation_deg", asJson(r.rotation)}};
  j[r.options.unit == RpeOptions::Delta::kTime ? "delta_s" : "delta_m"] = r.options.delta;
  return j;
}

json asJson(const DetectionResult& d) {
  json roc = json::array();
  for (const auto& c : d.roc) {
    json points = json::array();
    for (const auto& p : c.points) points.push_back({{"threshold", number(p.threshold)}, {"tpr", number(p.tpr)}, {"fpr", number(p.fpr)}});
    roc.push_back({{"score", c.score},
                   {"auc", number(c.auc)},
                   {"positives", c.positives},
                   {"negatives", c.negatives},
                   {"skipped", c.skipped},
                   {"points", points}});
  }
  json intervals = json::array();
  for (const auto& iv : d.intervals)
    intervals.push_back({{"label_start_ns", iv.label.start},
                         {"label_end_ns", iv.label.end},
                         {"frames", iv.frames},
                         {"detected_frames", iv.detected_frames},
                         {"onset_delay_s", number(iv.onset_delay_s)},
                         {"release_lag_s", number(iv.release_lag_s)}});
  return {{"frames", d.frames},
          {"rows_without_label", d.rows_without_label},
          {"labels_without_row", d.labels_without_row},
          {"tp", d.counts.tp},
          {"fp", d.counts.fp},
          {"tn", d.counts.tn},
          {"fn", d.counts.fn},
          {"tpr", number(d.counts.tpr())},
          {"fpr", number(d.counts.fpr())},
          {"precision", number(d.counts.precision())},
          {"f1", number(d.counts.f1())},
          {"hindsight", d.has_hindsight ? json{{"tp", d.hindsight.tp},
                                               {"fp", d.hindsight.fp},
                                               {"tn", d.hindsight.tn},
                                               {"fn", d.hindsight.fn},
                                               {"tpr", number(d.hindsight.tpr())},
                                               {"fpr", number(d.hindsight.fpr())}}
                                        : json(nullptr)},
          {"intervals", intervals},
          {"roc", roc}};
}

/// One line of the comparison table.
struct MetricRow {
  std::string key;    ///< JSON key
  std::string label;  ///< Markdown label with unit
  int decimals;
  bool is_error;      ///< lower is better: gets a reduction vs the baseline
  std::function<double(const EstimateEvaluation&)> value;
};

double aucOf(const EstimateEvaluation& e, const std::string& score) {
  if (!e.detection) return kNaN;
  for (const auto& c : e.detection->roc) {
    if (c.score == score) return c.auc;
  }
  return kNaN;
}

std::string formatDelta(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::vector<MetricRow> metricRows(const EvaluationReport& report) {
  const std::string ds = formatDelta(report.options.rpe_delta_s) + " s";
  const std::string dm = formatDelta(report.options.rpe_delta_m) + " m";
  std::vector<MetricRow> rows = {
      {"ate_se3_rmse_m", "ATE SE(3) RMSE [m]", 4, true, [](const auto& e) { return e.ate_se3.translation.rmse; }},
      {"ate_se3_mean_m", "ATE SE(3) mean [m]", 4, true, [](const auto& e) { return e.ate_se3.translation.mean; }},
      {"ate_se3_median_m", "ATE SE(3) median [m]", 4, true, [](const auto& e) { return e.ate_se3.translation.median; }},
      {"ate_se3_max_m", "ATE SE(3) max [m]", 4, true, [](const auto& e) { return e.ate_se3.translation.max; }},
      {"ate_se3_rotation_rmse_deg", "ATE SE(3) rotation RMSE [deg]", 3, true, [](const auto& e) { return e.ate_se3.rotation.rmse; }},
      {"ate_posyaw_rmse_m", "ATE pos+yaw RMSE [m]", 4, true, [](const auto& e) { return e.ate_posyaw.translation.rmse; }},
      {"ate_posyaw_max_m", "ATE pos+yaw max [m]", 4, true, [](const auto& e) { return e.ate_posyaw.translation.max; }},
  };
  bool any_online = false;
  for (const auto& e : report.estimates) any_online = any_online || e.ate_posyaw_online.has_value();
  if (any_online)
    rows.push_back({"ate_posyaw_online_rmse_m", "ATE pos+yaw RMSE, per-frame output [m]", 4, true,
                    [](const auto& e) { return e.onlineAtePosYawRmse(); }});
  if (report.labels) {
    rows.push_back({"ate_se3_in_conflict_rmse_m", "ATE SE(3) RMSE in conflict [m]", 4, true,
                    [](const auto& e) { return e.ate_se3_in_conflict.rmse; }});
    rows.push_back({"ate_posyaw_in_conflict_rmse_m", "ATE pos+yaw RMSE in conflict [m]", 4, true,
                    [](const auto& e) { return e.ate_posyaw_in_conflict.rmse; }});
    rows.push_back({"ate_se3_outside_conflict_rmse_m", "ATE SE(3) RMSE outside conflict [m]", 4, true,
                    [](const auto& e) { return e.ate_se3_outside_conflict.rmse; }});
  }
  rows.push_back({"rpe_time_translation_rmse_m", "RPE " + ds + " translation RMSE [m]", 4, true,
                  [](const auto& e) { return e.rpe_time.translation.rmse; }});
  rows.push_back({"rpe_time_rotation_rmse_deg", "RPE " + ds + " rotation RMSE [deg]", 3, true,
                  [](const auto& e) { return e.rpe_time.rotation.rmse; }});
  rows.push_back({"rpe_distance_translation_rmse_m", "RPE " + dm + " translation RMSE [m]", 4, true,
                  [](const auto& e) { return e.rpe_distance.translation.rmse; }});
  rows.push_back({"rpe_distance_rotation_rmse_deg", "RPE " + dm + " rotation RMSE [deg]", 3, true,
                  [](const auto& e) { return e.rpe_distance.rotation.rmse; }});
  bool any_detection = false;
  for (const auto& e : report.estimates) any_detection = any_detection || e.detection.has_value();
  if (any_detection) {
    const auto det = [](std::function<double(const DetectionResult&)> f) {
      return [f](const EstimateEvaluation& e) { return e.detection ? f(*e.detection) : kNaN; };
    };
    rows.push_back({"detection_tpr", "Detection TPR (per frame)", 3, false, det([](const auto& d) { return d.counts.tpr(); })});
    rows.push_back({"detection_fpr", "Detection FPR (per frame)", 3, false, det([](const auto& d) { return d.counts.fpr(); })});
    rows.push_back({"detection_tpr_hindsight", "Detection TPR (intervals in hindsight)", 3, false,
                    det([](const auto& d) { return d.has_hindsight ? d.hindsight.tpr() : kNaN; })});
    rows.push_back({"detection_fpr_hindsight", "Detection FPR (intervals in hindsight)", 3, false,
                    det([](const auto& d) { return d.has_hindsight ? d.hindsight.fpr() : kNaN; })});
    rows.push_back({"detection_precision", "Detection precision", 3, false, det([](const auto& d) { return d.counts.precision(); })});
    rows.push_back({"detection_f1", "Detection F1", 3, false, det([](const auto& d) { return d.counts.f1(); })});
    rows.push_back({"auc_propagated_chi2_ratio", "ROC AUC, chi2 / threshold", 3, false,
                    [](const auto& e) { return aucOf(e, "propagated_chi2_ratio"); }});
    rows.push_back({"auc_inconsistent_fraction", "ROC AUC, inconsistent fraction", 3, false,
                    [](const auto& e) { return aucOf(e, "inconsistent_fraction"); }});
    rows.push_back({"auc_evidence_score", "ROC AUC, evidence score", 3, false,
                    [](const auto& e) { return aucOf(e, "evidence_score"); }});
  }
  return rows;
}

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

std::string percent(double v) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%+.1f%%", v);
  return buf;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.flush();
  if (!out) throwCannotWrite(path, errno);
}

}  // namespace

double ReportWriter::relativeReduction(double baseline, double value) {
  if (!std::isfinite(baseline) || !std::isfinite(value) || baseline == 0) return kNaN;
  return 100.0 * (baseline - value) / baseline;
}

std::string ReportWriter::toJson(const EvaluationReport& report) {
  const auto& o = report.options;
  json j;
  j["ground_truth"] = {{"source", report.ground_truth_source},
                       {"poses", report.ground_truth_poses},
                       {"duration_s", report.ground_truth_duration_s},
                       {"path_length_m", report.ground_truth_path_length_m}};
  if (report.labels) {
    json intervals = json::array();
    for (const auto& i : report.labels->conflictIntervals()) {
      intervals.push_back({{"start_ns", i.start}, {"end_ns", i.end}, {"duration_s", i.durationSeconds()}});
    }
    j["labels"] = {{"source", report.labels->source()},
                   {"frames", report.labels->labels().size()},
                   {"conflict_frames", report.labels->conflictFrames()},
                   {"conflict_intervals", intervals}};
  } else {
    j["labels"] = nullptr;
  }
  j["options"] = {
      {"association",
       {{"method", o.association.method == AssociationOptions::Method::kNearest ? "nearest" : "interpolate"},
        {"max_interpolation_gap_s", o.association.max_interpolation_gap_s},
        {"max_time_difference_s", o.association.max_time_difference_s}}},
      {"alignment", {{"min_position_spread_m", o.alignment.min_position_spread_m}}},
      {"rpe_delta_s", o.rpe_delta_s},
      {"rpe_delta_m", o.rpe_delta_m},
      {"rpe_tolerance", o.rpe_tolerance},
      {"detection",
       {{"label_tolerance_s", o.detection.label_tolerance_s}, {"suspected_is_positive", o.detection.suspected_is_positive}}}};
  j["baseline"] = report.baseline;
  json estimates = json::array();
  for (const auto& e : report.estimates) {
    json je = {{"name", e.name},
               {"trajectory", e.trajectory_source},
               {"conflict_csv", e.detector_source.empty() ? json(nullptr) : json(e.detector_source)},
               {"poses", e.poses},
               {"ate", {{"se3", asJson(e.ate_se3)}, {"posyaw", asJson(e.ate_posyaw)}}},
               {"rpe", {{"time", asJson(e.rpe_time)}, {"distance", asJson(e.rpe_distance)}}}};
    if (e.ate_posyaw_online) je["ate"]["posyaw_online"] = asJson(*e.ate_posyaw_online);
    if (e.has_conflict_split) {
      je["ate"]["se3"]["in_conflict_translation_m"] = asJson(e.ate_se3_in_conflict);
      je["ate"]["se3"]["outside_conflict_translation_m"] = asJson(e.ate_se3_outside_conflict);
      je["ate"]["posyaw"]["in_conflict_translation_m"] = asJson(e.ate_posyaw_in_conflict);
    }
    je["detection"] = e.detection ? asJson(*e.detection) : json(nullptr);
    estimates.push_back(je);
  }
  j["estimates"] = estimates;
  // Flat metrics and reductions, the same numbers as the Markdown table.
  const auto rows = metricRows(report);
  const EstimateEvaluation* base = report.find(report.baseline);
  json metrics = json::object(), reductions = json::object();
  for (const auto& e : report.estimates) {
    json m = json::object(), r = json::object();
    for (const auto& row : rows) {
      m[row.key] = number(row.value(e));
      if (row.is_error && base && e.name != base->name) r[row.key] = number(relativeReduction(row.value(*base), row.value(e)));
    }
    metrics[e.name] = m;
    if (base && e.name != base->name) reductions[e.name] = r;
  }
  j["metrics"] = metrics;
  j["relative_reduction_percent"] = reductions;
  return j.dump(2) + "\n";
}

std::string ReportWriter::toMarkdown(const EvaluationReport& report) {
  std::ostringstream md;
  md << "## Trajectory evaluation\n\n";
  md << "Ground truth: `" << report.ground_truth_source << "` (" << report.ground_truth_poses << " poses, "
     << fixed(report.ground_truth_duration_s, 1) << " s, " << fixed(report.ground_truth_path_length_m, 2)
     << " m path).\n";
  if (report.labels) {
    double conflict_s = 0;
    for (const auto& i : report.labels->conflictIntervals()) conflict_s += i.durationSeconds();
    md << "Conflict labels: `" << report.labels->source() << "` (" << report.labels->labels().size() << " frames, "
       << report.labels->conflictFrames() << " in conflict, " << report.labels->conflictIntervals().size()
       << " interval(s), " << fixed(conflict_s, 1) << " s).\n";
  }
  md << "\n| Run | Poses | Matched | Trajectory |\n|---|---:|---:|---|\n";
  for (const auto& e : report.estimates) {
    md << "| " << e.name << (e.name == report.baseline && report.estimates.size() > 1 ? " (baseline)" : "") << " | "
       << e.poses << " | " << e.ate_se3.translation_errors.size() << " | `" << e.trajectory_source << "`"
       << (e.detector_source.empty() ? "" : ", `" + e.detector_source + "`") << " |\n";
  }
  const EstimateEvaluation* base = report.find(report.baseline);
  std::vector<const EstimateEvaluation*> compared;
  for (const auto& e : report.estimates) {
    if (base && e.name != base->name) compared.push_back(&e);
  }
  md << "\n| Metric |";
  for (const auto& e : report.estimates) md << " " << e.name << " |";
  for (const auto* e : compared) md << " " << e->name << " reduction vs " << base->name << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < report.estimates.size() + compared.size(); ++i) md << "---:|";
  md << "\n";
  for (const auto& row : metricRows(report)) {
    md << "| " << row.label << " |";
    for (const auto& e : report.estimates) md << " " << fixed(row.value(e), row.decimals) << " |";
    for (const auto* e : compared) {
      md << " " << (row.is_error ? percent(relativeReduction(row.value(*base), row.value(*e))) : "") << " |";
    }
    md << "\n";
  }
  if (report.labels && !report.labels->labels().empty()) {
    bool header = false;
    const Timestamp t0 = report.labels->labels().front().t;
    for (const auto& e : report.estimates) {
      if (!e.detection) continue;
      for (const auto& iv : e.detection->intervals) {
        if (!header) {
          md << "\nDetection per labelled interval (onset delay: first detected frame after the label starts; "
                "release lag: end of that detection after the label ends, negative if it let go before; "
                "n/a: never detected):\n\n"
             << "| Run | Labelled [s] | Frames detected | Onset delay [s] | Release lag [s] |\n|---|---|---:|---:|---:|\n";
          header = true;
        }
        md << "| " << e.name << " | " << fixed(toSeconds(iv.label.start - t0), 2) << " - "
           << fixed(toSeconds(iv.label.end - t0), 2) << " | " << iv.detected_frames << "/" << iv.frames << " | "
           << fixed(iv.onset_delay_s, 2) << " | " << fixed(iv.release_lag_s, 2) << " |\n";
      }
    }
  }
  // Decided on the ground truth, so the same for every run.
  std::string from_orientations;
  for (const AteResult* a : {&report.estimates.front().ate_se3, &report.estimates.front().ate_posyaw}) {
    if (a->rotation_from_orientations) {
      from_orientations += std::string(from_orientations.empty() ? "" : " and ") +
                           (a->alignment == Alignment::kSe3 ? "SE(3)" : "pos+yaw") + " (spread " +
                           fixed(a->position_spread_m, 3) + " m)";
    }
  }
  if (!from_orientations.empty()) {
    md << "\nGround-truth positions spread less than " << fixed(report.options.alignment.min_position_spread_m, 2)
       << " m, so the alignment rotation came from the orientations for " << from_orientations << ".\n";
  }
  if (!compared.empty()) {
    md << "\nReduction: 100 * (baseline - run) / baseline; positive = less error than " << base->name << ".\n";
  }
  return md.str();
}

void ReportWriter::write(const EvaluationReport& report, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir)) throw InputError(dir + ": cannot create report folder");
  writeText(dir + "/eval.json", toJson(report));
  writeText(dir + "/eval.md", toMarkdown(report));
  writeTum(report.ground_truth, dir + "/ground_truth.tum");
  for (const auto& e : report.estimates) {
    writeTum(Trajectory(e.ate_se3.aligned_estimate, e.name), dir + "/" + e.name + "_aligned_se3.tum");
  }
}

}  // namespace mcvio::evaluation
