#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mcvio::dataset {

/// Fast reader for EuRoC-style CSV files: the whole file is read at once and rows are split in
/// place (no per-field streams). Lines starting with '#' and blank lines are skipped; so is a
/// first line whose first field is not a number (a header without '#'). Fields are trimmed of
/// spaces; "\r\n" line ends are accepted. Quoting is not supported (EuRoC has none).
///
/// Parse errors throw mcvio::InputError as "<path>:<line>: <what>".
class CsvReader {
 public:
  /// Reads the file; throws mcvio::InputError if it does not exist or cannot be read.
  explicit CsvReader(std::string path);

  /// Advances to the next data row; false at the end of the file.
  bool nextRow();

  /// 1-based line number of the current row.
  std::size_t lineNumber() const { return line_number_; }
  std::size_t fieldCount() const { return fields_.size(); }
  std::string_view field(std::size_t i) const { return fields_[i]; }
  const std::string& path() const { return path_; }

  /// Throws unless the row has exactly `count` fields; `what` names the row kind in the message.
  void expectFieldCount(std::size_t count, const char* what) const;
  /// Field i as an integer; `column` names the column in an error message.
  std::int64_t int64At(std::size_t i, const char* column) const;
  /// Field i as a finite double (NaN and inf are errors).
  double doubleAt(std::size_t i, const char* column) const;

  /// "<path>:<line>" of the current row, for messages.
  std::string location() const;
  /// Throws mcvio::InputError "<path>:<line>: <message>".
  [[noreturn]] void fail(const std::string& message) const;

 private:
  std::string path_;
  std::string content_;
  std::size_t pos_ = 0;
  std::size_t line_number_ = 0;
  std::vector<std::string_view> fields_;
};

}  // namespace mcvio::dataset
