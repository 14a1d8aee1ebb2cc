#pragma once
#include <string>
#include <vector>
#include <utility>

#include "mcvio/evaluation/detector_record.hpp"

namespace mcvio::evaluation {

/// The per-frame conflict detector output of a run, as `mcvio run` writes OUT/conflict.csv:
///   timestamp_ns,state,propagated_chi2,propagated_threshold,landmarks_tested,
///   landmarks_inconsistent,inconsistent_fraction,coherence,interval_start_ns,resolution_mode,
///   interval_onset_ns,interval_end_ns
/// then frontend_checked,frontend_inconsistent,accel_bias_drift,split_chi2 (which no metric here
/// uses) and evidence_score (its own ROC and plot; `nan` on a frame nothing could test). The
/// header line (with or without a leading '#') says which columns are present and in which order;
/// only timestamp_ns and state are required, unknown columns are ignored. Without a header the
/// twelve columns above are assumed.
class DetectorLog {
 public:
  DetectorLog() = default;
  DetectorLog(std::vector<DetectorRecord> records, std::vector<std::string> columns,
              std::string source);

  /// Throws mcvio::InputError "<path>:<line>: column '<name>': ..." for a missing file, a
  /// header without timestamp_ns or state, a row whose field count differs from the header's,
  /// a field that is not a (finite) number, an unknown state or time that does not increase.
  static DetectorLog load(const std::string& path);

  const std::vector<DetectorRecord>& records() const { return records_; }
  bool empty() const { return records_.empty(); }
  std::size_t size() const { return records_.size(); }
  /// True if the file had this column (e.g. "inconsistent_fraction").
  bool hasColumn(const std::string& name) const;
  const std::vector<std::string>& columns() const { return columns_; }
  const std::string& source() const { return source_; }
  /// True if the file has the interval_onset_ns and interval_end_ns columns.
  bool hasHindsightIntervals() const { return hasColumn("interval_onset_ns") && hasColumn("interval_end_ns"); }
  /// The conflict intervals [m-, m+] in hindsight, in time order: every interval the rows name by
  /// its onset, ending where the rows say it closed, or at the last row if it never did.
  std::vector<std::pair<Timestamp, Timestamp>> hindsightIntervals() const;

 private:
  std::vector<DetectorRecord> records_;
  std::vector<std::string> columns_;
  std::string source_;
};

}  // namespace mcvio::evaluation
