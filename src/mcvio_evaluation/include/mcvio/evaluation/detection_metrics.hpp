#pragma once
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "mcvio/evaluation/conflict_label_timeline.hpp"
#include "mcvio/evaluation/detector_log.hpp"

namespace mcvio::evaluation {

struct DetectionOptions {
  /// A detector row and a label belong to the same frame if they are this close [s]; both come
  /// from the camera stamps, so a small value only absorbs rounding.
  double label_tolerance_s = 0.02;
  /// Count `suspected` frames as detections too (default: only `conflict`).
  bool suspected_is_positive = false;

  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

/// Per-frame confusion counts: positive = labelled in conflict.
struct ConfusionCounts {
  std::size_t tp = 0, fp = 0, tn = 0, fn = 0;
  double tpr() const;        ///< tp / (tp + fn); NaN without positives
  double fpr() const;        ///< fp / (fp + tn); NaN without negatives
  double precision() const;  ///< tp / (tp + fp); NaN without detections
  double f1() const;
};

struct RocPoint {
  double threshold = 0;  ///< frames with score >= threshold are detections
  double tpr = 0;
  double fpr = 0;
};

/// ROC of one detector score: one point per distinct score (from (0, 0) at +inf to (1, 1)).
struct RocCurve {
  std::string score;
  std::vector<RocPoint> points;
  double auc = 0;  ///< trapezoid area; NaN without both positives and negatives
  std::size_t positives = 0, negatives = 0;
  std::size_t skipped = 0;  ///< frames whose score is NaN (not computed that frame)
};

/// ROC of `scores` (higher = more conflict) against `positive`; NaN scores are skipped.
/// Throws std::invalid_argument if the sizes differ.
RocCurve computeRoc(const std::vector<double>& scores, const std::vector<bool>& positive,
                    const std::string& score_name);

/// How one labelled conflict interval was detected online: how late the detector came on and how
/// long it stayed on after the motion ended. Missed frames at the onset cost TPR, frames after
/// the end cost FPR, so these two explain a per-frame figure in seconds.
struct IntervalDetection {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  TimeInterval label;               ///< first to last labelled frame
  std::size_t frames = 0;           ///< detector rows matched to its labelled frames
  std::size_t detected_frames = 0;  ///< ... of them detected
  /// From the label's first frame to the first detected frame inside the interval [s]; NaN if
  /// the interval was never detected.
  double onset_delay_s = kNaN;
  /// The last frame of the detection that is on at the interval's last detected frame (followed
  /// past the interval's end while it stays on), minus the label's last frame [s]: > 0 the
  /// detector stayed on after the motion ended, < 0 it let go before. NaN if never detected.
  double release_lag_s = kNaN;
};

/// A run's detector against the labels.
struct DetectionResult {
  ConfusionCounts counts;
  std::size_t frames = 0;               ///< detector rows matched to a label
  std::size_t rows_without_label = 0;   ///< detector rows with no label nearby
  std::size_t labels_without_row = 0;   ///< labelled frames the run has no detector row for
  /// ROC per score column present in the log: "propagated_chi2_ratio" (chi2 / threshold),
  /// "inconsistent_fraction" and "evidence_score".
  std::vector<RocCurve> roc;
  /// The same frames counted against the run's conflict intervals in hindsight (onset where the
  /// evidence built up, end at the last frame with evidence), when the log has them.
  bool has_hindsight = false;
  ConfusionCounts hindsight;
  /// One entry per labelled interval (ConflictLabelTimeline::conflictIntervals()), in time order.
  std::vector<IntervalDetection> intervals;
  /// All labelled intervals as one, from the first one's start to the last one's end: onset at the
  /// first detection inside any of them, release at the end of the last such detection. For a
  /// sequence with one conflicting motion whose label flickers at the edges (a pedestrian's first
  /// pixels), so a one-frame label before the real onset does not stand for the whole. Default
  /// (NaN, no frames) without labelled intervals.
  IntervalDetection labelledSpan() const;
  /// Per matched frame, in time order (for plots).
  std::vector<Timestamp> times;
  std::vector<bool> labelled;
  std::vector<bool> detected;
  std::vector<double> evidence;  ///< the evidence score (NaN: untested, or not in the log)
};

/// Matches every detector row to the label of the same frame and counts TP/FP/TN/FN per frame.
DetectionResult evaluateDetection(const DetectorLog& log, const ConflictLabelTimeline& labels,
                                  const DetectionOptions& options = {});

}  // namespace mcvio::evaluation
