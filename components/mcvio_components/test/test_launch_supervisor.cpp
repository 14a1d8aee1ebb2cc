// LaunchSupervisor (`mcvio launch --processes`) with bash scripts for components (dash cannot
// write to descriptor 100): the order it
// starts and stops them in, and what it makes of a component that fails. The real components
// under it are checked by test/cli/cli_launch.sh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <csignal>
#include <map>
#include <sstream>
#include <unistd.h>

#include "mcvio/components/launch_supervisor.hpp"

using namespace mcvio::components;
using Kind = LaunchPlan::Kind;

namespace {

// A component that says it is listening, then works until its input ends (`cat`), as a
// frontend drains its queue.
const char* kListening = "echo start-$0 >> \"$LOG\"; printf 1 >&$MCVIO_LAUNCH_READY_FD; cat > /dev/null; echo stop-$0 >> \"$LOG\"";
// A player: plays a moment, then exits.
const char* kPlaying = "echo start-$0 >> \"$LOG\"; sleep 0.3; echo played-$0 >> \"$LOG\"";

LaunchPlan::Entry entry(Kind kind, const std::string& name) {
  LaunchPlan::Entry e;
  e.kind = kind;
  e.name = name;
  return e;
}

struct Scripted {
  std::string log;
  LaunchPlan plan;
  std::map<std::string, std::string> scripts;  // by component name

  Scripted() : log(::testing::TempDir() + "/supervisor_" + std::to_string(getpid()) + ".log") {
    std::filesystem::remove(log);
    plan.source = "test.yaml";
    ::setenv("LOG", log.c_str(), 1);
  }
  void add(Kind kind, const std::string& name, const std::string& script) {
    plan.entries.push_back(entry(kind, name));
    scripts[name] = script;
  }
  LaunchSupervisor::Result run() {
    LaunchSupervisor::Options o;
    o.start_timeout_s = 10;
    o.stop_timeout_s = 5;
    plan.drain_timeout_s = 5;
    std::ostringstream said;
    LaunchSupervisor supervisor(plan, [this](const LaunchPlan::Entry& e) {
      return std::vector<std::string>{"/bin/bash", "-c", scripts.at(e.name), e.name};
    }, o, &said);
    auto r = supervisor.run();
    std::cout << said.str() << LaunchSupervisor::summary(r);
    return r;
  }
  std::vector<std::string> lines() const {
    std::ifstream in(log);
    std::vector<std::string> out;
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
  }
};

}  // namespace

TEST(LaunchSupervisor, StartsInTheFilesOrderPlayersLastAndStopsInTheOrderDataFlows) {
  Scripted s;
  s.add(Kind::kRecorder, "rec", kListening);
  s.add(Kind::kPlayer, "pl", kPlaying);
  s.add(Kind::kBackend, "be", kListening);
  s.add(Kind::kFrontend, "fe", kListening);
  const auto r = s.run();
  EXPECT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.interrupted);
  ASSERT_EQ(r.children.size(), 4u);
  for (const auto& c : r.children) {
    EXPECT_EQ(c.exit_code, 0) << c.name;
    EXPECT_GT(c.pid, 0) << c.name;
  }
  // Each listening component is up before the next starts; once the player has exited the
  // frontend is told first, the recorder last, each after the one before has exited.
  const std::vector<std::string> expected{"start-rec", "start-be", "start-fe", "start-pl", "played-pl",
                                          "stop-fe",   "stop-be",  "stop-rec"};
  EXPECT_EQ(s.lines(), expected);
}

TEST(LaunchSupervisor, AComponentThatExitsBeforeItStartsEndsTheLaunch) {
  Scripted s;
  s.add(Kind::kRecorder, "rec", kListening);
  s.add(Kind::kFrontend, "fe", "echo start-$0 >> \"$LOG\"; exit 3");
  s.add(Kind::kPlayer, "pl", kPlaying);
  const auto r = s.run();
  EXPECT_EQ(r.error, "frontend 'fe' exited with 3 before it started");
  ASSERT_EQ(r.children.size(), 3u);
  EXPECT_EQ(r.children[0].signal, SIGINT);  // the recorder got SIGINT (a real one closes its bag)
  EXPECT_EQ(r.children[1].exit_code, 3);
  EXPECT_EQ(r.children[2].pid, -1);  // the player never started
  EXPECT_EQ(s.lines(), (std::vector<std::string>{"start-rec", "start-fe"}));
}

TEST(LaunchSupervisor, AFailingPlayerOrAComponentThatDiesMidwayIsNamed) {
  {
    Scripted s;
    s.add(Kind::kBackend, "be", kListening);
    s.add(Kind::kPlayer, "pl", "exit 4");
    const auto r = s.run();
    EXPECT_EQ(r.error, "player 'pl' failed: it exited with 4");
    EXPECT_EQ(r.children[0].signal, SIGINT);
  }
  {
    Scripted s;
    s.add(Kind::kBackend, "be", "printf 1 >&$MCVIO_LAUNCH_READY_FD; kill -SEGV $$");
    s.add(Kind::kPlayer, "pl", "sleep 5");
    const auto r = s.run();
    EXPECT_EQ(r.error, "backend 'be' was ended by signal 11 (Segmentation fault) while the launch ran");
    EXPECT_EQ(r.children[1].signal, SIGINT);  // the player was stopped, not waited for
  }
}

TEST(LaunchSupervisor, AComponentThatNeverSaysItIsListeningTimesOut) {
  Scripted s;
  s.add(Kind::kFrontend, "fe", "sleep 30");
  LaunchSupervisor::Options o;
  o.start_timeout_s = 0.5;
  o.stop_timeout_s = 2;
  LaunchSupervisor supervisor(s.plan, [](const LaunchPlan::Entry&) {
    return std::vector<std::string>{"/bin/bash", "-c", "sleep 30"};
  }, o, nullptr);
  const auto r = supervisor.run();
  EXPECT_EQ(r.error.rfind("frontend 'fe' had not started after 0.5", 0), 0u) << r.error;
  EXPECT_EQ(r.children[0].signal, SIGINT);
}

TEST(LaunchSupervisor, AProgramThatCannotBeRunIsNamed) {
  Scripted s;
  s.add(Kind::kRecorder, "rec", "");
  LaunchSupervisor supervisor(s.plan, [](const LaunchPlan::Entry&) {
    return std::vector<std::string>{"/nonexistent/mcvio"};
  }, {}, nullptr);
  const auto r = supervisor.run();
  EXPECT_EQ(r.error, "recorder 'rec' exited with 127 before it started");
}

// `respawn`: a backend that crashes while the player plays is started again and the launch goes
// on to its normal end; one that cannot start again fails the launch instead of looping.
TEST(LaunchSupervisor, ARespawningComponentIsStartedAgainAndOneThatCannotStartFails) {
  // The first run crashes once it is listening; later runs listen until their input ends.
  const std::string marker = ::testing::TempDir() + "/supervisor_respawn_" + std::to_string(getpid());
  ::setenv("MARKER", marker.c_str(), 1);
  const std::string crashes_once =
      "if [ ! -e \"$MARKER\" ]; then touch \"$MARKER\"; echo start-$0 >> \"$LOG\"; printf 1 >&$MCVIO_LAUNCH_READY_FD; "
      "kill -SEGV $$; fi; " + std::string(kListening);
  {
    std::filesystem::remove(marker);
    Scripted s;
    s.add(Kind::kBackend, "be", crashes_once);
    s.plan.entries.back().respawn = true;
    s.plan.entries.back().respawn_delay_s = 0.2;
    s.add(Kind::kPlayer, "pl", "sleep 2; " + std::string(kPlaying));
    const auto r = s.run();
    EXPECT_TRUE(r.error.empty()) << r.error;
    ASSERT_EQ(r.children.size(), 2u);
    EXPECT_EQ(r.children[0].respawns, 1);
    EXPECT_EQ(r.children[0].exit_code, 0);  // the respawned one stopped cleanly at the end
    EXPECT_EQ(r.children[1].exit_code, 0);
    EXPECT_EQ(s.lines(), (std::vector<std::string>{"start-be", "start-be", "start-pl", "played-pl", "stop-be"}));
    EXPECT_NE(LaunchSupervisor::summary(r).find("respawned 1 time)"), std::string::npos) << LaunchSupervisor::summary(r);
  }
  {
    std::filesystem::remove(marker);
    Scripted s;
    s.add(Kind::kRecorder, "rec", kListening);
    s.add(Kind::kBackend, "be", "if [ ! -e \"$MARKER\" ]; then touch \"$MARKER\"; printf 1 >&$MCVIO_LAUNCH_READY_FD; "
                                "kill -SEGV $$; fi; exit 3");
    s.plan.entries.back().respawn = true;
    s.add(Kind::kPlayer, "pl", "sleep 5");
    const auto r = s.run();
    EXPECT_EQ(r.error, "backend 'be' exited with 3 before it had started again");
    EXPECT_EQ(r.children[0].signal, SIGINT);  // the recorder got SIGINT (a real one closes its bag)
    EXPECT_EQ(r.children[1].respawns, 1);
    EXPECT_EQ(r.children[2].signal, SIGINT);
  }
  {
    // Without respawn the same crash ends the launch.
    std::filesystem::remove(marker);
    Scripted s;
    s.add(Kind::kBackend, "be", crashes_once);
    s.add(Kind::kPlayer, "pl", "sleep 5");
    const auto r = s.run();
    EXPECT_EQ(r.error, "backend 'be' was ended by signal 11 (Segmentation fault) while the launch ran");
    EXPECT_EQ(r.children[0].respawns, 0);
  }
  std::filesystem::remove(marker);
  ::unsetenv("MARKER");
}
