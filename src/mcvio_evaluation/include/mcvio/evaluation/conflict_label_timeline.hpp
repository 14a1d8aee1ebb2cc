#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mcvio/dataset/conflict_label.hpp"

namespace mcvio::evaluation {

/// A closed time span [start, end] of consecutive frames labelled in conflict.
struct TimeInterval {
  Timestamp start = 0;
  Timestamp end = 0;
  double durationSeconds() const { return toSeconds(end - start); }
};

/// The ground-truth conflict labels of a sequence (one per camera frame, mav0/conflict_labels.csv)
/// with lookups by time.
class ConflictLabelTimeline {
 public:
  ConflictLabelTimeline() = default;
  /// Labels in strictly increasing time (as EurocFileReader::readLabels returns them).
  explicit ConflictLabelTimeline(std::vector<dataset::ConflictLabel> labels, std::string source = {});

  /// `path`: the labels CSV, a EuRoC folder holding mav0/, or mav0/. Errors (mcvio::InputError,
  /// naming file and line) as EurocFileReader::readLabels; a folder without labels is an error.
  static ConflictLabelTimeline load(const std::string& path);

  /// The label of the frame nearest to t, if one lies within tolerance_s.
  std::optional<bool> inConflictAt(Timestamp t, double tolerance_s) const;
  /// Index in labels() of the frame nearest to t, if one lies within tolerance_s.
  std::optional<std::size_t> labelIndexAt(Timestamp t, double tolerance_s) const;

  /// Runs of consecutive in-conflict frames, each from its first to its last frame time.
  const std::vector<TimeInterval>& conflictIntervals() const { return intervals_; }
  const std::vector<dataset::ConflictLabel>& labels() const { return labels_; }
  std::size_t conflictFrames() const;
  bool empty() const { return labels_.empty(); }
  const std::string& source() const { return source_; }

 private:
  std::vector<dataset::ConflictLabel> labels_;
  std::vector<TimeInterval> intervals_;
  std::string source_;
};

}  // namespace mcvio::evaluation
