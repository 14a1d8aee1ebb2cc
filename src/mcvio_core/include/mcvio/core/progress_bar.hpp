#pragma once
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

namespace mcvio {

/// A one-line progress bar on stderr for long runs (simulation, playback, `mcvio run`). Draws only
/// when stderr is a terminal, at most ~10 times a second, so logs and CI output stay clean.
class ProgressBar {
 public:
  /// `label` prefixes the line; `total` is the number of steps (0 = unknown).
  ProgressBar(std::string label, std::size_t total, bool enabled = true);
  ~ProgressBar();
  /// Reports `done` steps and an optional detail ("frame 120/540, 2.1x real time").
  void update(std::size_t done, const std::string& detail = {});
  /// Draws the final state and ends the line.
  void finish(const std::string& detail = {});

 private:
  void draw(std::size_t done, const std::string& detail);
  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace mcvio
