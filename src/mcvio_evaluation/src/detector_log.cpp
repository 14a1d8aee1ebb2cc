#include "mcvio/evaluation/detector_log.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/csv_reader.hpp"

namespace mcvio::evaluation {

namespace {

const std::vector<std::string> kDefaultColumns = {
    "timestamp_ns",          "state",          "propagated_chi2", "propagated_threshold",
    "landmarks_tested",      "landmarks_inconsistent", "inconsistent_fraction",
    "coherence",             "interval_start_ns",      "resolution_mode",
    "interval_onset_ns",     "interval_end_ns"};

std::string trim(std::string s) {
  const auto not_space = [](unsigned char c) { return !std::isspace(c); };
  s.erase(s.begin(), std::find_if(s.begin(), s.end(), not_space));
  s.erase(std::find_if(s.rbegin(), s.rend(), not_space).base(), s.end());
  return s;
}

/// The first non-blank line, if it is a header (starts with '#' or a non-numeric field).
std::vector<std::string> readHeader(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file (missing or unreadable)");
  std::string line;
  while (std::getline(in, line)) {
    line = trim(line);
    if (line.empty()) continue;
    const bool hashed = line.front() == '#';
    if (hashed) line = trim(line.substr(1));
    if (!hashed && (std::isdigit(static_cast<unsigned char>(line.front())) || line.front() == '-' ||
                    line.front() == '+')) {
      return {};  // data straight away
    }
    std::vector<std::string> names;
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      names.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    // "timestamp [ns]" and "timestamp" name the time column too.
    for (auto& n : names) {
      if (n == "timestamp" || n == "timestamp [ns]" || n == "t_ns") n = "timestamp_ns";
    }
    return names;
  }
  return {};
}

}  // namespace

const char* toString(DetectorRecord::State state) {
  switch (state) {
    case DetectorRecord::State::kNone: return "none";
    case DetectorRecord::State::kSuspected: return "suspected";
    case DetectorRecord::State::kConflict: return "conflict";
  }
  return "none";
}

DetectorLog::DetectorLog(std::vector<DetectorRecord> records, std::vector<std::string> columns,
                         std::string source)
    : records_(std::move(records)), columns_(std::move(columns)), source_(std::move(source)) {}

std::vector<std::pair<Timestamp, Timestamp>> DetectorLog::hindsightIntervals() const {
  std::vector<std::pair<Timestamp, Timestamp>> intervals;
  for (const auto& r : records_) {
    if (r.interval_onset == 0) continue;
    if (intervals.empty() || intervals.back().first != r.interval_onset) intervals.emplace_back(r.interval_onset, 0);
    if (r.interval_end != 0) intervals.back().second = r.interval_end;
  }
  for (auto& iv : intervals)
    if (iv.second == 0) iv.second = records_.back().t;  // still open at the end of the run
  return intervals;
}

bool DetectorLog::hasColumn(const std::string& name) const {
  return std::find(columns_.begin(), columns_.end(), name) != columns_.end();
}

DetectorLog DetectorLog::load(const std::string& path) {
  std::vector<std::string> columns = readHeader(path);
  const bool headerless = columns.empty();
  if (headerless) columns = kDefaultColumns;
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < columns.size(); ++i) index.emplace(columns[i], i);
  for (const char* required : {"timestamp_ns", "state"}) {
    if (!index.count(required)) {
      throw InputError(path + ": header has no '" + required + "' column (header: " +
                       [&] {
                         std::string h;
                         for (const auto& c : columns) h += (h.empty() ? "" : ",") + c;
                         return h;
                       }() +
                       ")");
    }
  }
  const auto column = [&](const char* name) -> long {
    const auto it = index.find(name);
    return it == index.end() ? -1 : static_cast<long>(it->second);
  };
  const long c_t = column("timestamp_ns"), c_state = column("state"),
             c_chi2 = column("propagated_chi2"), c_thr = column("propagated_threshold"),
             c_tested = column("landmarks_tested"), c_incons = column("landmarks_inconsistent"),
             c_frac = column("inconsistent_fraction"), c_coh = column("coherence"),
             c_start = column("interval_start_ns"), c_mode = column("resolution_mode"),
             c_score = column("evidence_score");
  long c_onset = column("interval_onset_ns"), c_end = column("interval_end_ns");

  dataset::CsvReader csv(path);
  std::vector<DetectorRecord> records;
  while (csv.nextRow()) {
    // Files from before the hindsight columns: the first ten.
    if (headerless && records.empty() && csv.fieldCount() == kDefaultColumns.size() - 2 &&
        columns.size() == kDefaultColumns.size()) {
      columns.resize(kDefaultColumns.size() - 2);
      c_onset = c_end = -1;
    }
    if (csv.fieldCount() != columns.size()) {
      csv.fail("row has " + std::to_string(csv.fieldCount()) + " columns, the header " +
               std::to_string(columns.size()));
    }
    DetectorRecord r;
    r.t = csv.int64At(static_cast<std::size_t>(c_t), "timestamp_ns");
    const std::string_view state = csv.field(static_cast<std::size_t>(c_state));
    if (state == "none") {
      r.state = DetectorRecord::State::kNone;
    } else if (state == "suspected") {
      r.state = DetectorRecord::State::kSuspected;
    } else if (state == "conflict") {
      r.state = DetectorRecord::State::kConflict;
    } else {
      csv.fail("column 'state': '" + std::string(state) + "' is not none, suspected or conflict");
    }
    const auto number = [&](long c, const char* name, double& out) {
      if (c >= 0) out = csv.doubleAt(static_cast<std::size_t>(c), name);
    };
    const auto count = [&](long c, const char* name, int& out) {
      if (c < 0) return;
      const std::int64_t v = csv.int64At(static_cast<std::size_t>(c), name);
      if (v < 0 || v > 1'000'000'000) csv.fail(std::string("column '") + name + "': " + std::to_string(v) + " is not a count");
      out = static_cast<int>(v);
    };
    number(c_chi2, "propagated_chi2", r.propagated_chi2);
    number(c_thr, "propagated_threshold", r.propagated_threshold);
    count(c_tested, "landmarks_tested", r.landmarks_tested);
    count(c_incons, "landmarks_inconsistent", r.landmarks_inconsistent);
    number(c_frac, "inconsistent_fraction", r.inconsistent_fraction);
    number(c_coh, "coherence", r.coherence);
    if (c_start >= 0) r.interval_start = csv.int64At(static_cast<std::size_t>(c_start), "interval_start_ns");
    if (c_mode >= 0) r.resolution_mode = std::string(csv.field(static_cast<std::size_t>(c_mode)));
    const auto stamp = [&](long c, const char* name, Timestamp& out) {
      if (c < 0) return;
      out = csv.int64At(static_cast<std::size_t>(c), name);
      if (out < 0) csv.fail(std::string("column '") + name + "': " + std::to_string(out) + " is negative");
    };
    // "nan": a frame the detectors could not test.
    if (c_score >= 0 && csv.field(static_cast<std::size_t>(c_score)) != "nan") {
      const auto i = static_cast<std::size_t>(c_score);
      r.evidence_score = csv.doubleAt(i, "evidence_score");
      if (r.evidence_score < 0) csv.fail("column 'evidence_score': " + std::string(csv.field(i)) + " is negative");
    }
    stamp(c_onset, "interval_onset_ns", r.interval_onset);
    stamp(c_end, "interval_end_ns", r.interval_end);
    if (r.interval_end != 0 && r.interval_end < r.interval_onset) {
      csv.fail("column 'interval_end_ns': " + std::to_string(r.interval_end) + " precedes interval_onset_ns " +
               std::to_string(r.interval_onset));
    }
    if (!records.empty() && r.t <= records.back().t) {
      csv.fail("column 'timestamp_ns': " + std::to_string(r.t) + " does not increase (previous " +
               std::to_string(records.back().t) + ")");
    }
    records.push_back(std::move(r));
  }
  if (headerless && records.empty())
    throw InputError(path + ": is empty (no header, no rows); was the run that wrote it interrupted?");
  return DetectorLog(std::move(records), std::move(columns), path);
}

}  // namespace mcvio::evaluation
