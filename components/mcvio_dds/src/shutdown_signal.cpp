#include "mcvio/dds/shutdown_signal.hpp"

#include <atomic>
#include <csignal>
#include <thread>

namespace mcvio::dds {
namespace {

std::atomic<bool> g_requested{false};

extern "C" void onSignal(int) { g_requested.store(true); }

}  // namespace

void ShutdownSignal::install() {
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
}

bool ShutdownSignal::requested() { return g_requested.load(); }

void ShutdownSignal::request() { g_requested.store(true); }

bool ShutdownSignal::waitFor(std::chrono::milliseconds timeout) {
  // Polling: a signal handler may only touch lock-free atomics, so there is nothing to notify.
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!g_requested.load() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return g_requested.load();
}

}  // namespace mcvio::dds
