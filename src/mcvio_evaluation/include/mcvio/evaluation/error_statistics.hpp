#pragma once
#include <cstddef>
#include <vector>

namespace mcvio::evaluation {

/// Summary of a set of non-negative errors. With no errors, count is 0 and every value NaN
/// (written as null in JSON, "n/a" in tables) so an empty set is never mistaken for zero error.
struct ErrorStatistics {
  std::size_t count = 0;
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;

  static ErrorStatistics of(const std::vector<double>& errors);
};

}  // namespace mcvio::evaluation
