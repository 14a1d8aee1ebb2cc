#pragma once
#include <memory>
#include <string>
#include <vector>

#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/dds/generic_subscription.hpp"

namespace mcvio::components {

/// Replays a rosbag2 bag on the bus: every recorded topic (or a selection) with its recorded type
/// and the original timing between messages (scaled by `rate`), or lossless. The payloads go out
/// byte for byte as recorded, so types mcvio has no code for replay too.
class BagPlayer {
 public:
  BagPlayer(std::shared_ptr<dds::Node> node, const std::string& bag, PlayerOptions options,
            std::vector<std::string> topics = {});
  ~BagPlayer();
  PlaybackSummary run();

 private:
  std::shared_ptr<dds::Node> node_;
  std::string bag_;
  PlayerOptions options_;
  std::vector<std::string> topic_filter_;
};

}  // namespace mcvio::components
