#include "pong_monitor.hpp"

#include <cstdlib>
#include <ctime>

namespace mcvio::dds::bench {

std::int64_t steadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::int64_t processCpuNs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

void PongMonitor::onPong(std::uint32_t seq, std::int32_t count, const std::string& frame_id) {
  Pong pong;
  pong.arrival_ns = steadyNowNs();
  pong.count = count;
  // A stream ack carries the echo's CPU time as digits; an echoed ping carries "ping" (-> 0).
  pong.echo_cpu_ns = std::strtoll(frame_id.c_str(), nullptr, 10);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    any_ = true;
    seq_ = seq;
    last_ = pong;
  }
  arrived_.notify_one();
}

bool PongMonitor::waitFor(std::uint32_t seq, std::chrono::milliseconds timeout, Pong* pong) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!arrived_.wait_for(lock, timeout, [&] { return any_ && seq_ == seq; })) return false;
  *pong = last_;
  return true;
}

}  // namespace mcvio::dds::bench
