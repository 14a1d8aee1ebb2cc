#pragma once
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace mcvio::sim::detail {

/// Runs fn(i) for i in [0, n) on up to `threads` threads (the caller's thread included), handing
/// out indices dynamically. Results must not depend on which thread runs which index.
template <typename Fn>
void parallelFor(int n, int threads, Fn&& fn) {
  threads = std::max(1, std::min(threads, n));
  if (threads == 1) {
    for (int i = 0; i < n; ++i) fn(i);
    return;
  }
  std::atomic<int> next{0};
  auto worker = [&] {
    for (int i = next.fetch_add(1); i < n; i = next.fetch_add(1)) fn(i);
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<size_t>(threads - 1));
  for (int k = 1; k < threads; ++k) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

}  // namespace mcvio::sim::detail
