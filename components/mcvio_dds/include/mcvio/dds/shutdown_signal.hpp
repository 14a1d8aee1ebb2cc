#pragma once
#include <chrono>

namespace mcvio::dds {

/// SIGINT/SIGTERM turned into a flag that components poll or wait on, so Ctrl-C closes bags,
/// flushes files and leaves the DDS graph cleanly instead of dying mid-write.
class ShutdownSignal {
 public:
  /// Installs the handlers (idempotent).
  static void install();
  static bool requested();
  /// Requests shutdown from code (tests, a finished player).
  static void request();
  /// Blocks until a signal arrives or `timeout` passes; true when shutdown was requested.
  static bool waitFor(std::chrono::milliseconds timeout);
};

}  // namespace mcvio::dds
