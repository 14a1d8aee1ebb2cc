#pragma once
#include <string>
#include <vector>

#include "mcvio/components/backend_component.hpp"
#include "mcvio/components/frontend_component.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/components/recorder.hpp"
#include "mcvio/core/topic_remapping.hpp"

namespace mcvio::components {

/// What `mcvio launch` starts, resolved from a launch file (LaunchFile::resolve): every argument
/// substituted, every option checked. The Launcher runs it.
struct LaunchPlan {
  enum class Kind { kPlayer, kFrontend, kBackend, kRecorder };

  /// One component: the options of its kind are the ones used.
  struct Entry {
    Kind kind = Kind::kPlayer;
    std::string name;                 ///< node name, unique in the plan (default: the kind)
    std::string node_namespace = "/mcvio";
    /// `remap:` rules of the component's node (not recorders).
    TopicRemapping remapping;
    /// With `mcvio launch --processes`: a frontend or backend that ends while the launch runs is
    /// started again after respawn_delay_s, as ROS 2 launch's `respawn` does (in one process a
    /// crash ends the whole launch). One that then exits before it is listening fails the launch.
    bool respawn = false;
    double respawn_delay_s = 0;
    /// Player: a EuRoC folder or a rosbag2 bag; `topics` selects a bag's topics (empty: all).
    std::string input;
    std::vector<std::string> topics;
    PlayerOptions player;
    FrontendComponentOptions frontend;
    BackendComponentOptions backend;
    /// Recorder: the bag directory to create.
    std::string output;
    RecorderOptions recorder;
  };

  std::string source;  ///< the launch file, for messages
  std::vector<Entry> entries;  ///< in start order; stopped in reverse
  /// With at least one player: stop once every player has finished and the other components
  /// have handled what it published. False: run until Ctrl-C.
  bool exit_when_played = true;
  /// After the players: give up waiting for the frontends and backends after this long [s].
  double drain_timeout_s = 120.0;

  static const char* kindName(Kind kind);
  bool has(Kind kind) const;
};

}  // namespace mcvio::components
