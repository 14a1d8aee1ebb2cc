#pragma once
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "mcvio/components/launch_plan.hpp"
#include "mcvio/dds/participant.hpp"

namespace mcvio::components {

/// Runs a LaunchPlan in this process, as a ROS 2 component container would: each component on a
/// participant of its own (so each shows up as its own node), recorders first, players last.
/// With players and `exit_when_played`, it stops once every player has finished and the
/// frontends, backends and recorders have handled what the players published; otherwise (or
/// on the first Ctrl-C, dds::ShutdownSignal) it stops then. Stopping flushes the backends and
/// closes the bags, so nothing received is lost.
class Launcher {
 public:
  /// What each component did, in the plan's order.
  struct EntryResult {
    std::string name;
    LaunchPlan::Kind kind = LaunchPlan::Kind::kPlayer;
    PlaybackSummary playback;
    FrontendComponentStats frontend;
    BackendComponentStats backend;
    RecordingSummary recording;
    std::string error;  ///< a player that failed (its message); the others still stop cleanly
  };
  struct Result {
    std::vector<EntryResult> entries;
    bool interrupted = false;  ///< stopped by Ctrl-C / SIGTERM
    bool drained = true;       ///< false: drain_timeout_s passed before the pipeline caught up
    double wall_seconds = 0;
  };

  /// Hooks for a component run in a process of its own (LaunchSupervisor).
  struct Control {
    /// Called once every component has started, before the players play.
    std::function<void()> started;
    /// Polled while a plan without players runs: true = the data has ended; handle what is
    /// queued (as after a player, bounded by drain_timeout_s), then stop.
    std::function<bool()> data_ended;
  };

  /// `participant`: domain and profiles; each component's participant is named mcvio_<name>.
  /// `log`: progress lines and the summary (nullptr: silent).
  Launcher(LaunchPlan plan, dds::ParticipantOptions participant, std::ostream* log);

  /// Starts every component and runs until the plan says stop. Throws mcvio::InputError or
  /// std::runtime_error when a component cannot start (a missing calibration, a bag directory
  /// that exists); what was started is stopped first.
  Result run(const Control& control = {});

  /// One line per component, as the single commands print at their end.
  static std::string summary(const Result& result);

 private:
  LaunchPlan plan_;
  dds::ParticipantOptions participant_;
  std::ostream* log_;
};

}  // namespace mcvio::components
