#pragma once
// Row loop helpers shared by the EuRoC CSV readers (internal to mcvio_dataset).
#include <string>
#include <vector>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/time.hpp"
#include "mcvio/dataset/csv_reader.hpp"

namespace mcvio::dataset::detail {

/// Runs parse_row on every data row; with skip_bad_rows an InputError only skips its row and
/// its message goes to `warnings` (if non-null).
template <typename ParseRow>
void forEachRow(CsvReader& csv, bool skip_bad_rows, std::vector<std::string>* warnings,
                ParseRow parse_row) {
  while (csv.nextRow()) {
    try {
      parse_row(csv);
    } catch (const InputError& e) {
      if (!skip_bad_rows) throw;
      if (warnings) warnings->push_back(std::string(e.what()) + " (row skipped)");
    }
  }
}

/// Strictly increasing time per file. A row failing this is not accepted, so `last` keeps the
/// last accepted row's time.
class IncreasingTime {
 public:
  void check(const CsvReader& csv, Timestamp t) {
    if (have_last_ && t <= last_) {
      csv.fail(t == last_ ? "duplicate timestamp " + std::to_string(t)
                          : "timestamp " + std::to_string(t) +
                                " is earlier than the previous row's " + std::to_string(last_));
    }
    last_ = t;
    have_last_ = true;
  }

 private:
  Timestamp last_ = 0;
  bool have_last_ = false;
};

}  // namespace mcvio::dataset::detail
