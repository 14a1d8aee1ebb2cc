#include "mcvio/dataset/csv_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>

#include "mcvio/core/input_error.hpp"

namespace mcvio::dataset {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

bool looksNumeric(std::string_view s) {
  return !s.empty() && (std::isdigit(static_cast<unsigned char>(s.front())) || s.front() == '-' ||
                        s.front() == '+' || s.front() == '.');
}

}  // namespace

CsvReader::CsvReader(std::string path) : path_(std::move(path)) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path_.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) throw InputError(path_ + ": cannot open file (missing or unreadable)");
  if (std::fseek(file.get(), 0, SEEK_END) == 0) {
    const long size = std::ftell(file.get());
    if (size > 0) content_.reserve(static_cast<std::size_t>(size));
    std::rewind(file.get());
  }
  char buffer[1 << 16];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof(buffer), file.get())) > 0) content_.append(buffer, n);
  if (std::ferror(file.get())) throw InputError(path_ + ": read error");
  fields_.reserve(32);
}

bool CsvReader::nextRow() {
  while (pos_ < content_.size()) {
    const std::size_t end = std::min(content_.find('\n', pos_), content_.size());
    std::string_view line(content_.data() + pos_, end - pos_);
    pos_ = end + 1;
    ++line_number_;
    line = trim(line);
    if (line.empty() || line.front() == '#') continue;
    fields_.clear();
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      if (comma == std::string_view::npos) {
        fields_.push_back(trim(line.substr(start)));
        break;
      }
      fields_.push_back(trim(line.substr(start, comma - start)));
      start = comma + 1;
    }
    if (line_number_ == 1 && !looksNumeric(fields_.front())) continue;  // header without '#'
    return true;
  }
  fields_.clear();
  return false;
}

void CsvReader::expectFieldCount(std::size_t count, const char* what) const {
  if (fields_.size() != count) {
    fail(std::string(what) + " row has " + std::to_string(fields_.size()) + " columns, expected " +
         std::to_string(count));
  }
}

std::int64_t CsvReader::int64At(std::size_t i, const char* column) const {
  const std::string_view f = fields_[i];
  std::int64_t value = 0;
  const char* first = f.data();
  if (!f.empty() && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, f.data() + f.size(), value);
  if (f.empty() || ec != std::errc() || ptr != f.data() + f.size()) {
    fail(std::string("column '") + column + "': '" + std::string(f) + "' is not an integer" +
         (ec == std::errc::result_out_of_range ? " in int64 range" : ""));
  }
  return value;
}

double CsvReader::doubleAt(std::size_t i, const char* column) const {
  const std::string_view f = fields_[i];
  double value = 0.0;
  const char* first = f.data();
  if (!f.empty() && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, f.data() + f.size(), value);
  if (f.empty() || ec != std::errc() || ptr != f.data() + f.size()) {
    fail(std::string("column '") + column + "': '" + std::string(f) + "' is not a number");
  }
  if (!std::isfinite(value)) {
    fail(std::string("column '") + column + "': value '" + std::string(f) + "' is not finite");
  }
  return value;
}

std::string CsvReader::location() const { return path_ + ":" + std::to_string(line_number_); }

void CsvReader::fail(const std::string& message) const {
  throw InputError(location() + ": " + message);
}

}  // namespace mcvio::dataset
