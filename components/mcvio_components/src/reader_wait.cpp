#include "mcvio/components/reader_wait.hpp"

#include <chrono>
#include <iostream>
#include <sstream>
#include <thread>

#include "mcvio/dds/shutdown_signal.hpp"

namespace mcvio::components {
namespace {

std::vector<std::string> shortOfReaders(const std::vector<ReaderDemand>& demands) {
  std::vector<std::string> topics;
  for (const auto& d : demands)
    if (d.writer->matchedReaders() < d.readers) topics.push_back(d.writer->topic());
  return topics;
}

std::string joined(const std::vector<std::string>& topics) {
  std::ostringstream s;
  for (std::size_t i = 0; i < topics.size(); ++i) s << (i ? ", " : "") << topics[i];
  return s.str();
}

}  // namespace

ReaderWaitResult waitForReaders(const std::vector<ReaderDemand>& demands, double timeout_s, bool announce,
                                const std::string& who) {
  using Clock = std::chrono::steady_clock;
  ReaderWaitResult result;
  const auto start = Clock::now();
  const auto deadline = start + std::chrono::milliseconds(static_cast<long long>(timeout_s * 1000));
  bool announced = false;
  for (;;) {
    result.topics_without_readers = shortOfReaders(demands);
    if (result.topics_without_readers.empty()) return result;
    if (dds::ShutdownSignal::requested()) {
      result.interrupted = true;
      return result;
    }
    const auto now = Clock::now();
    if (now >= deadline) return result;
    if (announce && !announced && now - start >= std::chrono::seconds(1)) {
      std::cerr << who << ": waiting up to " << timeout_s << " s for readers of "
                << joined(result.topics_without_readers)
                << " (--wait-for-readers 0 starts at once; Ctrl-C stops)\n";
      announced = true;
    }
    dds::ShutdownSignal::waitFor(std::chrono::milliseconds(10));
  }
}

}  // namespace mcvio::components
