#include "mcvio/dds/shutdown_signal.hpp"

#include <atomic>
#include <csignal>
#include <thread>

namespace mcvio::dds {
namespace {

std::atomic<bool> g_requested{false};

// The first signal asks for a clean stop; a second one (an impatient Ctrl-C, or `timeout`
// following up) ends the process at once with the conventional status.
extern "C" void onSignal(int sig) {
  if (g_requested.exchange(true)) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

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
