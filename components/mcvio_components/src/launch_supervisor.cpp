#include "mcvio/components/launch_supervisor.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <thread>

#include "mcvio/dds/shutdown_signal.hpp"

extern char** environ;

namespace mcvio::components {
namespace {

using Clock = std::chrono::steady_clock;
using Kind = LaunchPlan::Kind;

constexpr const char* kReadyFdVariable = "MCVIO_LAUNCH_READY_FD";
constexpr int kChildReadyFd = 100;  // where a child finds its end of the ready pipe

struct Child {
  const LaunchPlan::Entry* entry = nullptr;
  pid_t pid = -1;
  int stdin_w = -1;  // the parent's end of the child's standard input
  int ready_r = -1;  // the parent's end of the ready pipe
  bool running = false;
  int exit_code = -1;  // -1 until it exits, or when a signal ended it
  int signal = 0;      // the signal that ended it
  int respawns = 0;    // times it was started again (`respawn`)
};

void closeFd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

std::string describeExit(int exit_code, int signal) {
  if (signal != 0) return "was ended by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
  return "exited with " + std::to_string(exit_code) + (exit_code == 130 ? " (interrupted)" : "");
}

std::string seconds(double s) {
  std::ostringstream os;
  os << s << " s";
  return os.str();
}

std::string label(const Child& c) {
  return std::string(LaunchPlan::kindName(c.entry->kind)) + " '" + c.entry->name + "'";
}

/// True once the child has exited (its code recorded).
bool reap(Child& c, bool block = false) {
  if (!c.running) return true;
  int status = 0;
  const pid_t r = ::waitpid(c.pid, &status, block ? 0 : WNOHANG);
  if (r == 0) return false;
  c.running = false;
  if (r == c.pid && WIFEXITED(status)) c.exit_code = WEXITSTATUS(status);
  if (r == c.pid && WIFSIGNALED(status)) c.signal = WTERMSIG(status);
  closeFd(c.stdin_w);
  closeFd(c.ready_r);
  return true;
}

/// Waits up to timeout_s for the child to exit (with `until_signal`, only until Ctrl-C); true when
/// it has.
bool waitExit(Child& c, double timeout_s, bool until_signal = false) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  while (!reap(c)) {
    if (Clock::now() >= deadline || (until_signal && dds::ShutdownSignal::requested())) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

/// For a child that has been sent SIGINT: SIGKILL if it has not exited within timeout_s. True
/// when it had to be killed.
bool killUnlessExited(Child& c, double timeout_s) {
  if (waitExit(c, timeout_s)) return false;
  ::kill(-c.pid, SIGKILL);
  reap(c, true);
  return true;
}

/// fork + exec with the child's standard input and ready pipe set up; "" or why it failed.
std::string spawn(const std::vector<std::string>& argv, Child* c) {
  if (argv.empty()) return "no command";
  int in[2], ready[2];
  if (::pipe2(in, O_CLOEXEC) != 0) return std::string("pipe: ") + std::strerror(errno);
  if (::pipe2(ready, O_CLOEXEC) != 0) {
    ::close(in[0]);
    ::close(in[1]);
    return std::string("pipe: ") + std::strerror(errno);
  }
  // Everything the child needs is built before fork: after it only async-signal-safe calls.
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string prefix = std::string(kReadyFdVariable) + "=";
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e)
    if (std::strncmp(*e, prefix.c_str(), prefix.size()) != 0) env.emplace_back(*e);
  env.push_back(prefix + std::to_string(kChildReadyFd));
  std::vector<char*> envp;
  for (auto& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);

  // A stop signal sent before the child has exec'd must not run the parent's handler there.
  sigset_t stop_signals, previous;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  ::pthread_sigmask(SIG_BLOCK, &stop_signals, &previous);
  const pid_t pid = ::fork();
  if (pid < 0) {
    const std::string why = std::string("fork: ") + std::strerror(errno);
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    for (int fd : {in[0], in[1], ready[0], ready[1]}) ::close(fd);
    return why;
  }
  if (pid == 0) {
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    ::setpgid(0, 0);  // a terminal's Ctrl-C reaches the parent only
    ::dup2(in[0], STDIN_FILENO);
    if (ready[1] == kChildReadyFd) ::fcntl(kChildReadyFd, F_SETFD, 0);
    else ::dup2(ready[1], kChildReadyFd);
    ::execve(args[0], args.data(), envp.data());
    ::_exit(127);
  }
  ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  ::setpgid(pid, pid);  // from this side too, so a signal sent right away finds the group
  ::close(in[0]);
  ::close(ready[1]);
  c->pid = pid;
  c->stdin_w = in[1];
  c->ready_r = ready[0];
  c->running = true;
  return "";
}

enum class Readiness { kReady, kExited, kTimedOut, kInterrupted };

Readiness waitReady(Child& c, double timeout_s) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  while (Clock::now() < deadline) {
    if (dds::ShutdownSignal::requested()) return Readiness::kInterrupted;
    pollfd p{c.ready_r, POLLIN, 0};
    const int n = ::poll(&p, 1, 100);
    if (n > 0) {
      char byte = 0;
      const ssize_t got = ::read(c.ready_r, &byte, 1);
      if (got == 1) return Readiness::kReady;
      if (got == 0) {  // the child closed the pipe without a word: it is exiting
        reap(c, true);
        return Readiness::kExited;
      }
    }
    if (reap(c)) return Readiness::kExited;
  }
  return Readiness::kTimedOut;
}

}  // namespace

LaunchSupervisor::LaunchSupervisor(LaunchPlan plan, CommandFor command, Options options, std::ostream* log)
    : plan_(std::move(plan)), command_(std::move(command)), options_(options), log_(log) {}

LaunchSupervisor::Result LaunchSupervisor::run() {
  const auto t0 = Clock::now();
  dds::ShutdownSignal::install();
  const auto say = [this](const std::string& line) {
    if (log_) *log_ << "mcvio launch: " << line << "\n" << std::flush;
  };
  Result result;
  const auto fail = [&](const std::string& why) {
    if (result.error.empty()) result.error = why;
    say(why);
  };
  std::vector<Child> children(plan_.entries.size());
  // A component with `respawn` that ended while the launch ran: after its delay it is started
  // again and waited for as at the start; one that cannot start again fails the launch, so a
  // broken component does not respawn forever.
  const auto respawn = [&](Child& c) {
    ++c.respawns;
    const double delay = c.entry->respawn_delay_s;
    say(label(c) + " " + describeExit(c.exit_code, c.signal) + " while the launch ran; respawning it" +
        (delay > 0 ? " in " + seconds(delay) : "") + " (respawn " + std::to_string(c.respawns) + ")");
    if (delay > 0 &&
        dds::ShutdownSignal::waitFor(std::chrono::milliseconds(static_cast<long long>(delay * 1000.0 + 0.5))))
      return;
    c.exit_code = -1;
    c.signal = 0;
    const std::string why = spawn(command_(*c.entry), &c);
    if (!why.empty()) return fail("cannot respawn " + label(c) + ": " + why);
    say("started " + label(c) + " again (pid " + std::to_string(c.pid) + ")");
    const auto r = waitReady(c, options_.start_timeout_s);
    if (r == Readiness::kExited) fail(label(c) + " " + describeExit(c.exit_code, c.signal) + " before it had started again");
    if (r == Readiness::kTimedOut) fail(label(c) + " had not started again after " + seconds(options_.start_timeout_s));
  };
  for (std::size_t i = 0; i < children.size(); ++i) children[i].entry = &plan_.entries[i];

  // Start: everything but the players in the file's order, each once it is listening; then the
  // players.
  for (int pass = 0; pass < 2 && result.error.empty() && !dds::ShutdownSignal::requested(); ++pass) {
    for (auto& c : children) {
      if ((c.entry->kind == Kind::kPlayer) != (pass == 1)) continue;
      const auto argv = command_(*c.entry);
      const std::string why = spawn(argv, &c);
      if (!why.empty()) {
        fail("cannot start " + label(c) + ": " + why);
        break;
      }
      say("started " + label(c) + " (pid " + std::to_string(c.pid) + ")");
      if (pass == 1) continue;
      const auto r = waitReady(c, options_.start_timeout_s);
      if (r == Readiness::kReady) continue;
      if (r == Readiness::kInterrupted) break;
      if (r == Readiness::kExited) fail(label(c) + " " + describeExit(c.exit_code, c.signal) + " before it started");
      else fail(label(c) + " had not started after " + std::to_string(options_.start_timeout_s) + " s");
      break;
    }
  }

  // Run until the players are done (or, without players or exit_when_played, until Ctrl-C); a
  // component that ends on its own before that is a failure.
  const bool has_players = plan_.has(Kind::kPlayer);
  while (result.error.empty() && !dds::ShutdownSignal::requested()) {
    bool players_running = false;
    for (auto& c : children) {
      const bool was_running = c.running;
      if (!reap(c) || !was_running) {
        if (c.running && c.entry->kind == Kind::kPlayer) players_running = true;
        continue;
      }
      if (c.entry->kind == Kind::kPlayer) {
        if (c.exit_code != 0 || c.signal != 0) fail(label(c) + " failed: it " + describeExit(c.exit_code, c.signal));
        else say(label(c) + " has played everything");
      } else if (c.entry->respawn) {
        respawn(c);
      } else {
        fail(label(c) + " " + describeExit(c.exit_code, c.signal) + " while the launch ran");
      }
    }
    if (!result.error.empty()) break;
    if (has_players && !players_running && plan_.exit_when_played) break;
    dds::ShutdownSignal::waitFor(std::chrono::milliseconds(100));
  }

  // Stop. After a signal or a failure every component gets SIGINT at once (they close their bags);
  // after a normal end each kind in turn is told the data has ended and exits once it has handled
  // its queue.
  const auto stopNow = [&] {
    for (auto& c : children)
      if (c.running) ::kill(-c.pid, SIGINT);
    for (auto& c : children)
      if (c.running && killUnlessExited(c, options_.stop_timeout_s))
        say(label(c) + " did not exit " + std::to_string(options_.stop_timeout_s) + " s after SIGINT; killed it");
  };
  result.interrupted = dds::ShutdownSignal::requested();
  if (!result.error.empty() || result.interrupted) {
    stopNow();
  } else {
    for (const Kind kind : {Kind::kPlayer, Kind::kFrontend, Kind::kBackend, Kind::kRecorder}) {
      const double timeout = options_.stop_timeout_s +
                             (kind == Kind::kFrontend || kind == Kind::kBackend ? plan_.drain_timeout_s : 0.0);
      for (auto& c : children)
        if (c.running && c.entry->kind == kind) closeFd(c.stdin_w);
      for (auto& c : children) {
        if (!c.running || c.entry->kind != kind) continue;
        if (!waitExit(c, timeout, true) && !dds::ShutdownSignal::requested()) {
          say(label(c) + " had not stopped " + std::to_string(timeout) + " s after the data ended; sending SIGINT");
          ::kill(-c.pid, SIGINT);
          killUnlessExited(c, options_.stop_timeout_s);
        }
        if (!c.running && (c.exit_code != 0 || c.signal != 0)) fail(label(c) + " " + describeExit(c.exit_code, c.signal) + " as it stopped");
      }
      if (dds::ShutdownSignal::requested()) break;
    }
    result.interrupted = dds::ShutdownSignal::requested();
    if (result.interrupted) stopNow();
  }
  for (const auto& c : children)
    result.children.push_back({c.entry->name, c.entry->kind, c.pid, c.exit_code, c.signal, c.respawns});
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return result;
}

std::string LaunchSupervisor::summary(const Result& result) {
  std::ostringstream os;
  for (const auto& c : result.children) {
    os << "  " << LaunchPlan::kindName(c.kind) << " '" << c.name << "': ";
    if (c.pid < 0) os << "not started";
    else os << "process " << c.pid << ", " << (c.exit_code == 0 ? "exited cleanly" : describeExit(c.exit_code, c.signal));
    if (c.respawns > 0) os << " (respawned " << c.respawns << (c.respawns == 1 ? " time)" : " times)");
    os << "\n";
  }
  os << "  " << result.wall_seconds << " s" << (result.interrupted ? ", interrupted" : "") << "\n";
  return os.str();
}

void LaunchSupervisor::notifyStarted() {
  const char* fd_text = std::getenv(kReadyFdVariable);
  if (fd_text == nullptr) return;
  const int fd = std::atoi(fd_text);
  if (fd <= STDERR_FILENO) return;
  const char byte = '1';
  [[maybe_unused]] const ssize_t written = ::write(fd, &byte, 1);
  ::close(fd);
}

bool LaunchSupervisor::stopRequestedByParent() {
  static std::atomic<bool> ended{false};
  if (ended.load()) return true;
  if (!runningUnderSupervisor()) return false;
  pollfd p{STDIN_FILENO, POLLIN, 0};
  if (::poll(&p, 1, 0) <= 0) return false;
  if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) {
    ended = true;
  } else if (p.revents & POLLIN) {
    char buffer[64];
    if (::read(STDIN_FILENO, buffer, sizeof buffer) <= 0) ended = true;  // the parent writes nothing
  }
  return ended.load();
}

bool LaunchSupervisor::runningUnderSupervisor() { return std::getenv(kReadyFdVariable) != nullptr; }

}  // namespace mcvio::components
