#include "mcvio/evaluation/conflict_label_timeline.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_file_reader.hpp"

namespace mcvio::evaluation {

namespace fs = std::filesystem;

ConflictLabelTimeline::ConflictLabelTimeline(std::vector<dataset::ConflictLabel> labels,
                                             std::string source)
    : labels_(std::move(labels)), source_(std::move(source)) {
  bool open = false;
  for (const auto& l : labels_) {
    if (l.in_conflict && !open) {
      intervals_.push_back({l.t, l.t});
      open = true;
    } else if (l.in_conflict) {
      intervals_.back().end = l.t;
    } else {
      open = false;
    }
  }
}

ConflictLabelTimeline ConflictLabelTimeline::load(const std::string& path) {
  const fs::path p(path);
  fs::path csv = p;
  if (fs::is_directory(p)) {
    csv = fs::exists(p / "mav0" / "conflict_labels.csv") ? p / "mav0" / "conflict_labels.csv"
                                                          : p / "conflict_labels.csv";
    if (!fs::exists(csv)) {
      throw InputError(path + ": no conflict labels (expected " +
                       (p / "mav0" / "conflict_labels.csv").string() + ")");
    }
  }
  auto labels = dataset::EurocFileReader::readLabels(csv.string());
  if (labels.empty()) throw InputError(csv.string() + ": contains no labels");
  return ConflictLabelTimeline(std::move(labels), csv.string());
}

std::optional<bool> ConflictLabelTimeline::inConflictAt(Timestamp t, double tolerance_s) const {
  const auto i = labelIndexAt(t, tolerance_s);
  if (!i) return std::nullopt;
  return labels_[*i].in_conflict;
}

std::optional<std::size_t> ConflictLabelTimeline::labelIndexAt(Timestamp t, double tolerance_s) const {
  if (labels_.empty()) return std::nullopt;
  const auto it = std::lower_bound(labels_.begin(), labels_.end(), t,
                                   [](const dataset::ConflictLabel& l, Timestamp v) { return l.t < v; });
  const Timestamp tol = static_cast<Timestamp>(std::llround(tolerance_s * 1e9));
  const dataset::ConflictLabel* best = nullptr;
  Timestamp best_diff = 0;
  if (it != labels_.end()) {
    best = &*it;
    best_diff = it->t - t;
  }
  if (it != labels_.begin() && (!best || t - (it - 1)->t < best_diff)) {
    best = &*(it - 1);
    best_diff = t - best->t;
  }
  if (!best || best_diff > tol) return std::nullopt;
  return static_cast<std::size_t>(best - labels_.data());
}

std::size_t ConflictLabelTimeline::conflictFrames() const {
  return static_cast<std::size_t>(std::count_if(labels_.begin(), labels_.end(),
                                                [](const auto& l) { return l.in_conflict; }));
}

}  // namespace mcvio::evaluation
