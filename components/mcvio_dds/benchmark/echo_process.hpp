#pragma once
#include <sys/types.h>

#include <string>

#include "bench_transport.hpp"

namespace mcvio::dds::bench {

/// The echo end in a separate process: this executable started again with `--echo ...`.
/// fork + exec rather than a bare fork, because a forked copy of a process that already runs Fast
/// DDS threads would inherit half-held locks. The child runs until its stdin closes, i.e. until
/// this object is destroyed or the benchmark process dies.
class EchoProcess {
 public:
  /// Starts `<this executable> --echo <type_key> <transport> <domain> <udp profiles file> <udp
  /// profile>`. Throws std::runtime_error when the process cannot be started.
  EchoProcess(const std::string& type_key, Transport transport, const BusConfig& bus);
  /// Closes the child's stdin and waits for it to leave (its participants clean up their
  /// shared-memory segments); kills it after 10 s.
  ~EchoProcess();
  EchoProcess(const EchoProcess&) = delete;
  EchoProcess& operator=(const EchoProcess&) = delete;

  /// True once the child has exited (e.g. it failed to create its participants).
  bool exited();

 private:
  pid_t pid_ = -1;
  int stdin_fd_ = -1;
  bool reaped_ = false;
};

/// The child's side: parses `--echo ...` and echoes with both the wrapper and bare Fast DDS until
/// stdin closes. Returns the process exit code.
int runEchoProcess(int argc, char** argv);

}  // namespace mcvio::dds::bench
