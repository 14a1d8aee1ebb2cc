#pragma once
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "mcvio/components/launch_plan.hpp"

namespace mcvio::components {

/// Runs each component of a LaunchPlan in a process of its own, as `ros2 launch` runs nodes
/// (`mcvio launch --processes`). The parent starts the components in the plan's order, each once
/// the one before has said it is listening, the players last; when every player has exited it
/// stops the rest in the order data flows (frontends, backends, recorders), each after it has
/// handled what it received; Ctrl-C (or SIGTERM) stops every component at once, bags closed.
/// A frontend or backend with `respawn` that ends while the launch runs is started again (after
/// its respawn_delay) instead of ending the launch.
///
/// The protocol with a child (`mcvio launch FILE ... --node NAME`, see the static helpers):
/// - the child writes one byte to the descriptor named by $MCVIO_LAUNCH_READY_FD once its
///   component has started;
/// - its standard input is a pipe from the parent; end of file means "the players are done:
///   handle what is queued, then stop";
/// - each child runs in a process group of its own, so a Ctrl-C at the terminal reaches the parent
///   alone, which passes one SIGINT on to each child's group (a second one would end it at once).
class LaunchSupervisor {
 public:
  struct Options {
    /// A component that has not said it is listening after this long fails the launch [s].
    double start_timeout_s = 60.0;
    /// After the signal to stop: how long a component may take to exit before it gets SIGINT,
    /// and then as long again before SIGKILL [s]. The plan's drain_timeout_s is added for the
    /// frontends and backends, which may have a queue to work through.
    double stop_timeout_s = 15.0;
  };

  struct ChildResult {
    std::string name;
    LaunchPlan::Kind kind = LaunchPlan::Kind::kPlayer;
    int pid = -1;
    int exit_code = -1;  ///< -1: never started, or ended by a signal
    int signal = 0;      ///< the signal that ended it (0: it exited)
    int respawns = 0;    ///< times it was started again (LaunchPlan::Entry::respawn); pid is the last
  };
  struct Result {
    std::vector<ChildResult> children;  ///< in the plan's order
    bool interrupted = false;           ///< stopped by Ctrl-C / SIGTERM
    std::string error;                  ///< the first component that failed, and how; empty: none
    double wall_seconds = 0;
  };

  /// `command(entry)`: the child's command line (argv[0] is the program to run).
  using CommandFor = std::function<std::vector<std::string>(const LaunchPlan::Entry&)>;

  LaunchSupervisor(LaunchPlan plan, CommandFor command, Options options, std::ostream* log);

  /// Starts every component and runs until the plan says stop; see the class comment.
  Result run();

  static std::string summary(const Result& result);

  /// In a child: tells the parent the component is listening (nothing when not started by one).
  static void notifyStarted();
  /// In a child started by a parent: true once the parent closed our standard input.
  static bool stopRequestedByParent();
  /// True when this process was started by a LaunchSupervisor.
  static bool runningUnderSupervisor();

 private:
  LaunchPlan plan_;
  CommandFor command_;
  Options options_;
  std::ostream* log_;
};

}  // namespace mcvio::components
