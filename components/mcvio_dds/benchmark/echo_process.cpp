#include "echo_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "bare_ping_pong.hpp"
#include "bench_messages.hpp"
#include "bench_topics.hpp"
#include "wrapper_ping_pong.hpp"

namespace mcvio::dds::bench {

EchoProcess::EchoProcess(const std::string& type_key, Transport transport, const BusConfig& bus) {
  int fds[2];
  // Close-on-exec so a later echo child does not inherit this child's stdin and keep it open.
  if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed for the echo process");
  std::vector<std::string> args = {"/proc/self/exe",
                                   "--echo",
                                   type_key,
                                   transportName(transport),
                                   std::to_string(bus.domain_id),
                                   bus.udp_profiles_file,
                                   bus.udp_profile_name,
                                   bus.bare_in_own_participant ? "own" : "shared"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_ = fork();
  if (pid_ < 0) {
    close(fds[0]);
    close(fds[1]);
    throw std::runtime_error("fork failed for the echo process");
  }
  if (pid_ == 0) {
    // Only async-signal-safe calls between fork and exec.
    dup2(fds[0], STDIN_FILENO);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    execv("/proc/self/exe", argv.data());
    _exit(127);
  }
  close(fds[0]);
  stdin_fd_ = fds[1];
}

bool EchoProcess::exited() {
  if (reaped_) return true;
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) == pid_) reaped_ = true;
  return reaped_;
}

EchoProcess::~EchoProcess() {
  close(stdin_fd_);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!exited() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!reaped_) {
    std::fprintf(stderr, "dds_benchmark: echo process %d did not exit, killing it\n",
                 static_cast<int>(pid_));
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
}

namespace {

template <class T>
int echoUntilStdinCloses(Transport transport, const BusConfig& bus) {
  const std::string key = BenchMessage<T>::kKey;
  auto participant =
      Participant::create(wrapperParticipantOptions(bus, transport, "dds_bench_echo"));
  auto node = participant->createNode("dds_bench_echo");
  auto wrapper = std::make_unique<WrapperEchoer<T>>(*node, wrapperTopic(key, "ping"),
                                                    wrapperTopic(key, "pong"));
  auto bare_participant = makeBareParticipant(bus, transport, *participant, "dds_bench_bare_echo");
  auto bare = std::make_unique<BareEchoer<T>>(*bare_participant, bareTopic(key, "ping"),
                                              bareTopic(key, "pong"));
  char buffer[64];
  while (read(STDIN_FILENO, buffer, sizeof buffer) > 0) {
  }
  bare.reset();
  bare_participant.reset();
  wrapper.reset();
  node.reset();
  participant.reset();
  return 0;
}

}  // namespace

int runEchoProcess(int argc, char** argv) {
  if (argc != 8) {
    std::fprintf(stderr,
                 "usage: %s --echo image|imu inproc|shm|udp DOMAIN UDP_PROFILES_FILE UDP_PROFILE "
                 "shared|own\n",
                 argv[0]);
    return 2;
  }
  try {
    const std::string key = argv[2];
    const Transport transport = parseTransport(argv[3]);
    BusConfig bus;
    bus.domain_id = std::stoi(argv[4]);
    bus.udp_profiles_file = argv[5];
    bus.udp_profile_name = argv[6];
    bus.bare_in_own_participant = std::string(argv[7]) == "own";
    if (key == BenchMessage<Image>::kKey) return echoUntilStdinCloses<Image>(transport, bus);
    if (key == BenchMessage<Imu>::kKey) return echoUntilStdinCloses<Imu>(transport, bus);
    std::fprintf(stderr, "dds_benchmark --echo: unknown message '%s' (expected image or imu)\n",
                 key.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dds_benchmark --echo: %s\n", e.what());
  }
  return 1;
}

}  // namespace mcvio::dds::bench
