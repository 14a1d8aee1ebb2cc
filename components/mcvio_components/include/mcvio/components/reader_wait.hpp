#pragma once
#include <string>
#include <vector>

#include "mcvio/dds/endpoint.hpp"

namespace mcvio::components {

/// What a player waits for before its first message: so many readers on each of its writers.
struct ReaderDemand {
  const dds::WriterEndpoint* writer = nullptr;
  int readers = 1;
};

/// The outcome of waitForReaders.
struct ReaderWaitResult {
  std::vector<std::string> topics_without_readers;  ///< still short of their readers at the deadline
  bool interrupted = false;                         ///< Ctrl-C / SIGTERM arrived while waiting
};

/// Waits until every writer has its readers, `timeout_s` at most in all (one deadline for every
/// topic, not one per topic), and returns at once on a shutdown request: an unattended player
/// must stay stoppable. When `announce`, a wait longer than a second says on stderr what it
/// waits for and how to skip it; `who` prefixes that line ("mcvio play").
ReaderWaitResult waitForReaders(const std::vector<ReaderDemand>& demands, double timeout_s, bool announce,
                                const std::string& who);

}  // namespace mcvio::components
