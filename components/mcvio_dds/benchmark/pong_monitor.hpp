#pragma once
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>

namespace mcvio::dds::bench {

/// Steady-clock nanoseconds (CLOCK_MONOTONIC: one clock for every process on the host).
std::int64_t steadyNowNs();

/// CPU time of this whole process (all threads), for a cost per message that load from other
/// processes on a shared machine barely changes.
std::int64_t processCpuNs();

/// Where the measuring side's pong callback leaves the last echo and its arrival time, stamped in
/// the callback itself so the waiting thread's wake-up is not counted.
class PongMonitor {
 public:
  /// What one pong carried, plus when it arrived.
  struct Pong {
    std::int64_t arrival_ns = 0;   ///< steadyNowNs() in the callback
    std::int32_t count = 0;        ///< messages the echo end counted (stream acks)
    std::int64_t echo_cpu_ns = 0;  ///< the echo process's CPU time when it acked (stream acks)
  };
  /// Called from the pong reader's callback with the echoed header.
  void onPong(std::uint32_t seq, std::int32_t count, const std::string& frame_id);
  /// Waits until the pong of `seq` arrived; false on timeout.
  bool waitFor(std::uint32_t seq, std::chrono::milliseconds timeout, Pong* pong);

 private:
  std::mutex mutex_;
  std::condition_variable arrived_;
  bool any_ = false;
  std::uint32_t seq_ = 0;
  Pong last_;
};

}  // namespace mcvio::dds::bench
