#pragma once
#include <atomic>
#include <cstdint>
#include <string>

#include "pong_monitor.hpp"

namespace mcvio::dds::bench {

// The ping-pong protocol, carried in the message header so Image and Imu need no extra fields:
// header.stamp.nanosec is the sequence number, header.frame_id says what the echo side does.
inline const std::string kPingFrame = "ping";      ///< echo it back unchanged (latency)
inline const std::string kStreamFrame = "stream";  ///< count it, send nothing (throughput)
/// Count it and ack: the count in stamp.sec, the echo process's CPU nanoseconds in frame_id.
inline const std::string kStreamEndFrame = "stream_end";

// QoS of the two legs. Pings (and throughput streams) use the lossless preset: the writer waits for
// a slow reader, so a burst measures delivered messages, never dropped ones. Pongs use the reliable
// keep-last default: the echo writes them from inside its reader callback, on the Fast DDS receive
// thread, and a keep-all writer there can block waiting for an ACKNACK that only that very thread
// would process (seen in this benchmark: the echo stalled for good after a few hundred pings over
// SHM). With one ping outstanding at a time keep-last 10 loses nothing.

/// The measuring end: sends on the ping topic, its pong reader feeds monitor().
template <class T>
class Prober {
 public:
  virtual ~Prober() = default;
  /// One write; false when a full keep-all history made it give up (the caller retries).
  virtual bool send(const T& msg) = 0;
  PongMonitor& monitor() { return monitor_; }

 protected:
  PongMonitor monitor_;
};

/// The echo end, kept alive for as long as pings may come.
class Echoer {
 public:
  virtual ~Echoer() = default;
};

/// What the echo end sends back for each received ping.
template <class T>
class EchoRule {
 public:
  template <class Send>
  void onPing(const T& msg, Send&& send) {
    const std::string& frame = msg.header().frame_id();
    if (frame == kPingFrame) {
      send(msg);
      return;
    }
    const std::int32_t count = ++streamed_;
    if (frame == kStreamEndFrame) {
      // A header-only ack: the end of an image stream need not travel back at full size.
      T ack;
      ack.header(msg.header());
      ack.header().stamp().sec(count);
      ack.header().frame_id(std::to_string(processCpuNs()));
      send(ack);
    }
  }

 private:
  std::atomic<std::int32_t> streamed_{0};
};

}  // namespace mcvio::dds::bench
