#include "mcvio/evaluation/detection_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>

namespace mcvio::evaluation {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double ratio(std::size_t a, std::size_t b) {
  return b == 0 ? kNaN : static_cast<double>(a) / static_cast<double>(b);
}

/// Onset delay and release lag of every labelled interval, from the matched frames of `r`.
std::vector<IntervalDetection> detectIntervals(const DetectionResult& r, const ConflictLabelTimeline& labels,
                                               double tolerance_s) {
  // Frames in time order (a log built in memory need not be sorted).
  std::vector<std::size_t> order(r.times.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return r.times[a] < r.times[b]; });
  const Timestamp tolerance = fromSeconds(tolerance_s);
  std::vector<IntervalDetection> out;
  for (const TimeInterval& iv : labels.conflictIntervals()) {
    IntervalDetection d;
    d.label = iv;
    std::optional<std::size_t> first, last;  // positions in `order`
    for (std::size_t k = 0; k < order.size(); ++k) {
      const std::size_t i = order[k];
      if (!r.labelled[i] || r.times[i] < iv.start - tolerance || r.times[i] > iv.end + tolerance) continue;
      ++d.frames;
      if (!r.detected[i]) continue;
      ++d.detected_frames;
      if (!first) first = k;
      last = k;
    }
    if (first) {
      d.onset_delay_s = toSeconds(r.times[order[*first]] - iv.start);
      std::size_t k = *last;
      while (k + 1 < order.size() && r.detected[order[k + 1]]) ++k;
      d.release_lag_s = toSeconds(r.times[order[k]] - iv.end);
    }
    out.push_back(d);
  }
  return out;
}

}  // namespace

void DetectionOptions::validate() const {
  if (!(label_tolerance_s >= 0) || !std::isfinite(label_tolerance_s)) {
    throw std::invalid_argument("detection.label_tolerance_s must be >= 0");
  }
}

double ConfusionCounts::tpr() const { return ratio(tp, tp + fn); }
double ConfusionCounts::fpr() const { return ratio(fp, fp + tn); }
double ConfusionCounts::precision() const { return ratio(tp, tp + fp); }
double ConfusionCounts::f1() const { return ratio(2 * tp, 2 * tp + fp + fn); }

RocCurve computeRoc(const std::vector<double>& scores, const std::vector<bool>& positive,
                    const std::string& score_name) {
  if (scores.size() != positive.size()) {
    throw std::invalid_argument("computeRoc: " + std::to_string(scores.size()) + " scores and " +
                                std::to_string(positive.size()) + " labels");
  }
  RocCurve roc;
  roc.score = score_name;
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    if (std::isnan(scores[i])) {
      ++roc.skipped;
      continue;
    }
    order.push_back(i);
    (positive[i] ? roc.positives : roc.negatives) += 1;
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
  const double P = static_cast<double>(roc.positives), N = static_cast<double>(roc.negatives);
  const auto rate = [](std::size_t k, double total) { return total > 0 ? static_cast<double>(k) / total : kNaN; };
  roc.points.push_back({std::numeric_limits<double>::infinity(), rate(0, P), rate(0, N)});
  std::size_t tp = 0, fp = 0;
  for (std::size_t k = 0; k < order.size();) {
    const double threshold = scores[order[k]];
    // Equal scores are one threshold: they switch together.
    while (k < order.size() && scores[order[k]] == threshold) {
      (positive[order[k]] ? tp : fp) += 1;
      ++k;
    }
    roc.points.push_back({threshold, rate(tp, P), rate(fp, N)});
  }
  if (roc.positives == 0 || roc.negatives == 0) {
    roc.auc = kNaN;
  } else {
    roc.auc = 0;
    for (std::size_t i = 1; i < roc.points.size(); ++i) {
      const auto& a = roc.points[i - 1];
      const auto& b = roc.points[i];
      roc.auc += (b.fpr - a.fpr) * 0.5 * (a.tpr + b.tpr);
    }
  }
  return roc;
}

IntervalDetection DetectionResult::labelledSpan() const {
  IntervalDetection span;
  if (intervals.empty()) return span;
  span.label = {intervals.front().label.start, intervals.back().label.end};
  for (const auto& iv : intervals) {
    span.frames += iv.frames;
    span.detected_frames += iv.detected_frames;
  }
  for (const auto& iv : intervals) {
    if (std::isnan(iv.onset_delay_s)) continue;
    span.onset_delay_s = toSeconds(iv.label.start - span.label.start) + iv.onset_delay_s;
    break;
  }
  for (auto iv = intervals.rbegin(); iv != intervals.rend(); ++iv) {
    if (std::isnan(iv->release_lag_s)) continue;
    span.release_lag_s = iv->release_lag_s - toSeconds(span.label.end - iv->label.end);
    break;
  }
  return span;
}

DetectionResult evaluateDetection(const DetectorLog& log, const ConflictLabelTimeline& labels,
                                  const DetectionOptions& options) {
  options.validate();
  DetectionResult r;
  std::vector<bool> label_seen(labels.labels().size(), false);
  std::vector<double> ratio_scores, fraction_scores;
  r.has_hindsight = log.hasHindsightIntervals();
  const auto intervals = r.has_hindsight ? log.hindsightIntervals() : std::vector<std::pair<Timestamp, Timestamp>>{};
  const auto inInterval = [&](Timestamp t) {
    return std::any_of(intervals.begin(), intervals.end(), [&](const auto& iv) { return t >= iv.first && t <= iv.second; });
  };
  for (const auto& row : log.records()) {
    const auto index = labels.labelIndexAt(row.t, options.label_tolerance_s);
    if (!index) {
      ++r.rows_without_label;
      continue;
    }
    label_seen[*index] = true;
    const bool labelled = labels.labels()[*index].in_conflict;
    const bool detected = row.state == DetectorRecord::State::kConflict ||
                          (options.suspected_is_positive && row.state == DetectorRecord::State::kSuspected);
    if (labelled) {
      (detected ? r.counts.tp : r.counts.fn) += 1;
    } else {
      (detected ? r.counts.fp : r.counts.tn) += 1;
    }
    if (r.has_hindsight) {
      const bool in_hindsight = inInterval(row.t);
      if (labelled) {
        (in_hindsight ? r.hindsight.tp : r.hindsight.fn) += 1;
      } else {
        (in_hindsight ? r.hindsight.fp : r.hindsight.tn) += 1;
      }
    }
    ++r.frames;
    r.times.push_back(row.t);
    r.labelled.push_back(labelled);
    r.detected.push_back(detected);
    r.evidence.push_back(row.evidence_score);
    ratio_scores.push_back(row.propagatedRatio());
    fraction_scores.push_back(row.inconsistent_fraction);
  }
  r.intervals = detectIntervals(r, labels, options.label_tolerance_s);
  r.labels_without_row = static_cast<std::size_t>(std::count(label_seen.begin(), label_seen.end(), false));
  if (log.hasColumn("propagated_chi2")) {
    r.roc.push_back(computeRoc(ratio_scores, r.labelled, "propagated_chi2_ratio"));
  }
  if (log.hasColumn("inconsistent_fraction")) {
    r.roc.push_back(computeRoc(fraction_scores, r.labelled, "inconsistent_fraction"));
  }
  if (log.hasColumn("evidence_score")) {
    r.roc.push_back(computeRoc(r.evidence, r.labelled, "evidence_score"));
  }
  return r;
}

}  // namespace mcvio::evaluation
