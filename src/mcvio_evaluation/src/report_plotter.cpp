#include "mcvio/evaluation/report_plotter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "mcvio/core/input_error.hpp"

namespace mcvio::evaluation {

namespace {

const char* kConflictLabel = "labelled conflict";

double since(Timestamp t, Timestamp t0) { return toSeconds(t - t0); }

void shadeIntervals(PlotCanvas& canvas, const EvaluationReport& report, Timestamp t0) {
  if (!report.labels) return;
  for (const auto& i : report.labels->conflictIntervals()) {
    canvas.addXBand(since(i.start, t0), since(i.end, t0), ReportPlotter::conflictColor(), kConflictLabel, 0.3);
  }
}

std::string aucText(double auc) {
  if (!std::isfinite(auc)) return "AUC n/a";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "AUC %.3f", auc);
  return buf;
}

}  // namespace

cv::Scalar ReportPlotter::runColor(std::size_t i) {
  // Tableau-like palette without grey and red-orange (ground truth and shading).
  static const cv::Scalar palette[] = {{180, 119, 31}, {44, 160, 44}, {189, 103, 148}, {34, 189, 188},
                                       {207, 190, 23}, {194, 119, 227}, {75, 86, 140}};
  return palette[i % (sizeof(palette) / sizeof(palette[0]))];
}

cv::Scalar ReportPlotter::groundTruthColor() { return {30, 30, 30}; }

cv::Scalar ReportPlotter::conflictColor() { return {80, 130, 255}; }

std::vector<std::string> ReportPlotter::write(const EvaluationReport& report, const std::string& dir,
                                              const PlotStyle& style) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir)) throw InputError(dir + ": cannot create report folder");
  std::vector<std::string> written;
  // Ground truth only where the runs are (plus half a second): a long sequence would otherwise
  // dwarf a short run.
  Timestamp t_begin = report.ground_truth.endTime(), t_end = report.ground_truth.startTime();
  for (const auto& e : report.estimates) {
    if (e.ate_se3.aligned_estimate.empty()) continue;
    t_begin = std::min(t_begin, e.ate_se3.aligned_estimate.front().t);
    t_end = std::max(t_end, e.ate_se3.aligned_estimate.back().t);
  }
  if (t_end < t_begin) std::swap(t_begin, t_end);
  Trajectory gt;
  for (const auto& p : report.ground_truth.poses()) {
    if (p.t >= t_begin - 500'000'000 && p.t <= t_end + 500'000'000) gt.append(p);
  }
  const Timestamp t0 = t_begin;
  const std::string time_label = "time since the first evaluated pose [s]";

  // Top view.
  {
    PlotCanvas c("Trajectory, top view (runs aligned to ground truth, SE(3))", style);
    c.setXLabel("x [m]");
    c.setYLabel("y [m]");
    c.setEqualAspect(true);
    if (report.labels) {
      for (const auto& interval : report.labels->conflictIntervals()) {
        std::vector<double> x, y;
        for (const auto& p : gt.poses()) {
          if (p.t >= interval.start && p.t <= interval.end) {
            x.push_back(p.p.x());
            y.push_back(p.p.y());
          }
        }
        c.addLine(x, y, ReportPlotter::conflictColor(), kConflictLabel, 14, false, 0.45);
      }
    }
    std::vector<double> x, y;
    for (const auto& p : gt.poses()) {
      x.push_back(p.p.x());
      y.push_back(p.p.y());
    }
    c.addLine(x, y, ReportPlotter::groundTruthColor(), "ground truth", 2, true);
    for (std::size_t i = 0; i < report.estimates.size(); ++i) {
      std::vector<double> ex, ey;
      for (const auto& p : report.estimates[i].ate_se3.aligned_estimate) {
        ex.push_back(p.p.x());
        ey.push_back(p.p.y());
      }
      c.addLine(ex, ey, runColor(i), report.estimates[i].name, 2);
    }
    written.push_back(dir + "/trajectory_top.png");
    c.save(written.back());
  }
  // Side view: height over time.
  {
    PlotCanvas c("Height over time (runs aligned to ground truth, SE(3))", style);
    c.setXLabel(time_label);
    c.setYLabel("z [m]");
    shadeIntervals(c, report, t0);
    std::vector<double> t, z;
    for (const auto& p : gt.poses()) {
      t.push_back(since(p.t, t0));
      z.push_back(p.p.z());
    }
    c.addLine(t, z, ReportPlotter::groundTruthColor(), "ground truth", 2, true);
    for (std::size_t i = 0; i < report.estimates.size(); ++i) {
      std::vector<double> et, ez;
      for (const auto& p : report.estimates[i].ate_se3.aligned_estimate) {
        et.push_back(since(p.t, t0));
        ez.push_back(p.p.z());
      }
      c.addLine(et, ez, runColor(i), report.estimates[i].name, 2);
    }
    written.push_back(dir + "/trajectory_side.png");
    c.save(written.back());
  }
  // Error over time.
  {
    PlotCanvas c("Absolute position error over time (SE(3) alignment)", style);
    c.setXLabel(time_label);
    c.setYLabel("position error [m]");
    shadeIntervals(c, report, t0);
    double max_error = 0;
    for (std::size_t i = 0; i < report.estimates.size(); ++i) {
      const auto& ate = report.estimates[i].ate_se3;
      std::vector<double> t;
      for (const auto& p : ate.aligned_estimate) t.push_back(since(p.t, t0));
      for (double e : ate.translation_errors) max_error = std::max(max_error, e);
      char label[160];
      std::snprintf(label, sizeof(label), "%s (RMSE %.3f m)", report.estimates[i].name.c_str(), ate.translation.rmse);
      c.addLine(t, ate.translation_errors, runColor(i), label, 2);
    }
    // Errors are >= 0: start the axis at zero.
    c.setYRange(0, max_error > 0 ? max_error * 1.08 : 1.0);
    c.setXRange(0, std::max(toSeconds(t_end - t_begin), 1e-3));
    written.push_back(dir + "/error_over_time.png");
    c.save(written.back());
  }
  // Evidence over time: how far each run's detectors were from firing, frame by frame.
  bool any_evidence = false;
  for (const auto& e : report.estimates)
    if (e.detection)
      any_evidence = any_evidence || std::any_of(e.detection->evidence.begin(), e.detection->evidence.end(),
                                                 [](double s) { return std::isfinite(s); });
  if (any_evidence) {
    constexpr double kTop = 3.0;  // above that a frame is plainly in conflict; the shape is below 1
    PlotCanvas c("Conflict evidence over time (detector statistics / thresholds)", style);
    c.setXLabel(time_label);
    c.setYLabel("evidence score (clipped at 3)");
    shadeIntervals(c, report, t0);
    const double x_max = std::max(toSeconds(t_end - t_begin), 1e-3);
    c.addLine({0, x_max}, {1, 1}, cv::Scalar(90, 90, 90), "a detector fires (1)", 1, true);
    c.addLine({0, x_max}, {0.1, 0.1}, cv::Scalar(160, 160, 160), "hindsight onset level (0.1)", 1, true);
    for (std::size_t i = 0; i < report.estimates.size(); ++i) {
      const auto& e = report.estimates[i];
      if (!e.detection) continue;
      std::vector<double> t, s;
      for (std::size_t k = 0; k < e.detection->times.size(); ++k) {
        t.push_back(since(e.detection->times[k], t0));
        s.push_back(std::min(e.detection->evidence[k], kTop));
      }
      c.addLine(t, s, runColor(i), e.name, 1);
    }
    c.setYRange(0, kTop);
    c.setXRange(0, x_max);
    written.push_back(dir + "/evidence_over_time.png");
    c.save(written.back());
  }
  // ROC.
  bool any_roc = false;
  for (const auto& e : report.estimates) any_roc = any_roc || (e.detection && !e.detection->roc.empty());
  if (any_roc) {
    PlotCanvas c("Conflict detection ROC (per frame)", style);
    c.setXLabel("false positive rate");
    c.setYLabel("true positive rate");
    // A little room so curves along the edges are not hidden by the frame.
    c.setXRange(-0.02, 1.02);
    c.setYRange(-0.02, 1.02);
    c.addLine({0, 1}, {0, 1}, cv::Scalar(160, 160, 160), "chance", 1, true);
    for (std::size_t i = 0; i < report.estimates.size(); ++i) {
      const auto& e = report.estimates[i];
      if (!e.detection) continue;
      for (const auto& roc : e.detection->roc) {
        std::vector<double> fpr, tpr;
        for (const auto& p : roc.points) {
          fpr.push_back(p.fpr);
          tpr.push_back(p.tpr);
        }
        // One colour per run; the detectors' combined score solid and thick, the two statistics thin.
        const bool combined = roc.score == "evidence_score";
        const std::string what = combined                              ? ", evidence score ("
                                 : roc.score == "propagated_chi2_ratio" ? ", chi2 / threshold ("
                                                                        : ", inconsistent fraction (";
        c.addLine(fpr, tpr, runColor(i), e.name + what + aucText(roc.auc) + ")", combined ? 3 : 1,
                  roc.score == "inconsistent_fraction");
      }
    }
    written.push_back(dir + "/roc.png");
    c.save(written.back());
  }
  return written;
}

}  // namespace mcvio::evaluation
