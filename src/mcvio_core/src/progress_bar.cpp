#include "mcvio/core/progress_bar.hpp"

#include <unistd.h>

namespace mcvio {

ProgressBar::ProgressBar(std::string label, std::size_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && !finished_) std::fputc('\n', stderr);
}

void ProgressBar::update(std::size_t done, const std::string& detail) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100) && done != total_) return;
  last_draw_ = now;
  draw(done, detail);
}

void ProgressBar::finish(const std::string& detail) {
  if (!enabled_ || finished_) return;
  draw(total_, detail);
  std::fputc('\n', stderr);
  finished_ = true;
}

void ProgressBar::draw(std::size_t done, const std::string& detail) {
  constexpr int kWidth = 30;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double frac = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 0.0;
  std::string bar(kWidth, ' ');
  const int filled = static_cast<int>(frac * kWidth);
  for (int i = 0; i < filled && i < kWidth; ++i) bar[i] = '=';
  if (filled < kWidth) bar[filled] = '>';
  char eta[32] = "";
  if (frac > 0.01 && frac < 1.0) std::snprintf(eta, sizeof eta, " eta %.0fs", elapsed * (1 - frac) / frac);
  std::fprintf(stderr, "\r%s [%s] %3.0f%% %.0fs%s %s\033[K", label_.c_str(), bar.c_str(), frac * 100, elapsed, eta,
               detail.c_str());
  std::fflush(stderr);
}

}  // namespace mcvio
