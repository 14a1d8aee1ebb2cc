#include "mcvio/components/bag_player.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include "mcvio/components/playback_pacer.hpp"
#include "mcvio/components/reader_wait.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/core/progress_bar.hpp"
#include "mcvio/dds/shutdown_signal.hpp"
#include "mcvio/interfaces/type_names.hpp"

namespace mcvio::components {

BagPlayer::BagPlayer(std::shared_ptr<dds::Node> node, const std::string& bag, PlayerOptions options,
                     std::vector<std::string> topics)
    : node_(std::move(node)), bag_(bag), options_(options), topic_filter_(std::move(topics)) {
  options_.validate();
  if (!node_->remapping().empty()) {
    // A rule for a topic the bag does not hold does nothing: most likely a typo.
    std::set<std::string> names;
    const bag::BagReader reader(bag_);  // held: topics() refers into it
    for (const auto& t : reader.topics()) names.insert(t.name);
    for (const auto& r : node_->remapping().rules())
      if (!names.count(r.from))
        std::cerr << "mcvio play: warning: remap " << r.from << ":=" << r.to << ": " << bag_ << " has no topic " << r.from << "\n";
  }
}

BagPlayer::~BagPlayer() = default;

PlaybackSummary BagPlayer::run() {
  using Clock = std::chrono::steady_clock;
  PlaybackSummary summary;
  bag::BagReaderOptions ro;
  ro.topics = topic_filter_;
  // Publishers per topic, with the QoS the recording publishers offered (reliability and
  // durability), or lossless when asked.
  std::map<std::string, std::unique_ptr<dds::GenericPublisher>> pubs;
  {
    bag::BagReader probe(bag_, ro);
    for (const auto& w : probe.warnings()) std::cerr << "mcvio play: warning: " << bag_ << ": " << w << "\n";
    for (const auto& t : probe.topics()) {
      if (!topic_filter_.empty() && std::find(topic_filter_.begin(), topic_filter_.end(), t.name) == topic_filter_.end()) continue;
      dds::QosProfile q = dds::QosProfile::defaults();
      if (options_.lossless) {
        q = dds::QosProfile::lossless();
      } else if (t.offered_qos_profiles.find("reliability: 2") != std::string::npos) {
        q = dds::QosProfile::sensorData();
      }
      if (t.offered_qos_profiles.find("durability: 1") != std::string::npos && !options_.lossless) {
        q.durability = dds::QosProfile::Durability::kTransientLocal;
      }
      pubs[t.name] = std::make_unique<dds::GenericPublisher>(*node_, t.name, interfaces::rosToDdsTypeName(t.type),
                                                             t.type_description_hash, q);
    }
  }
  if (pubs.empty()) throw std::runtime_error("play: " + bag_ + " has none of the selected topics");
  if (options_.wait_for_readers_s > 0 && options_.min_readers > 0) {
    std::vector<ReaderDemand> demands;
    std::map<std::string, std::string> bag_name;  // published topic -> the bag's name for it
    for (auto& [name, p] : pubs) {
      demands.push_back({p.get(), options_.min_readers + (options_.extra_readers ? options_.extra_readers(p->topic()) : 0)});
      bag_name[p->topic()] = name;
    }
    const auto wait = waitForReaders(demands, options_.wait_for_readers_s, options_.progress, "mcvio play");
    if (wait.interrupted) {
      summary.interrupted = true;
      return summary;
    }
    if (!wait.topics_without_readers.empty()) {
      const std::string& topic = wait.topics_without_readers.front();
      if (options_.lossless)
        throw std::runtime_error("play: no reader of " + topic +
                                 (bag_name[topic] == topic ? std::string() : " (the bag's " + bag_name[topic] + ")") +
                                 " within " + std::to_string(options_.wait_for_readers_s) +
                                 " s; lossless playback needs its readers first");
      if (options_.progress)
        std::cerr << "mcvio play: no reader yet of " << wait.topics_without_readers.size() << " of " << demands.size()
                  << " topics (" << topic << (wait.topics_without_readers.size() > 1 ? ", ..." : "")
                  << "); playing anyway\n";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(options_.settle_s * 1000)));
  }
  const auto wall_start = Clock::now();
  do {
    bag::BagReader reader(bag_, ro);
    const std::size_t total = reader.metadata().message_count;
    ProgressBar bar("play", total, options_.progress);
    const auto pass_start = Clock::now();
    Timestamp t_first = -1;
    std::size_t done = 0, position = 0, in_range = 0;
    Timestamp t_end = -1;
    std::optional<PlaybackPacer> pacer;
    bool warned_backwards = false;
    bag::BagMessage m;
    while (!dds::ShutdownSignal::requested() && reader.next(m)) {
      ++position;
      if (t_first < 0) t_first = m.log_time + fromSeconds(options_.start_s);
      t_end = std::max(t_end, m.log_time);
      if (m.log_time < t_first) continue;
      ++in_range;
      if (options_.duration_s > 0 && m.log_time > t_first + fromSeconds(options_.duration_s)) break;
      if (!options_.lossless) {
        if (!pacer) pacer.emplace(t_first, options_.rate, options_.max_gap_s);
        const auto step = pacer->next(m.log_time);
        if (step.skipped_s > 0 || (step.backwards && !warned_backwards)) {
          std::cerr << "mcvio play: warning: " << reader.where(m) << " (message " << position
                    << (topic_filter_.empty() ? " of " + std::to_string(total) : std::string(" of the selection"))
                    << "): " << PlaybackPacer::describe(step, options_.max_gap_s) << "\n";
        }
        if (step.skipped_s > 0) {
          ++summary.shortened_gaps;
          summary.skipped_gap_seconds += step.skipped_s;
        }
        warned_backwards = warned_backwards || step.backwards;  // once per pass: the reader sorts
        std::this_thread::sleep_until(pass_start + step.wall_offset);
      }
      auto it = pubs.find(m.topic);
      if (it == pubs.end()) continue;
      // The DDS layer cannot send a payload without its 4-byte CDR header: a lossless write of
      // one retried for 60 s and then blamed the reader.
      if (m.data.size() < 4) {
        throw InputError(reader.where(m) + ": payload of " + std::to_string(m.data.size()) +
                         " bytes has no CDR header (4 bytes): it cannot be published");
      }
      if (!it->second->publish(m.data)) {
        throw std::runtime_error("play: a lossless reader of " + it->second->topic() + " stopped taking samples");
      }
      ++done;
      if (done % 20 == 0) bar.update(done, std::to_string(done) + " messages");
      summary.data_seconds = toSeconds(m.log_time - t_first);
    }
    bar.finish();
    if (in_range == 0 && position > 0 && options_.start_s > 0 && !dds::ShutdownSignal::requested())
      throw InputError("play: --start " + std::to_string(options_.start_s) + " s is past the end of " + bag_ + " (" +
                       std::to_string(toSeconds(t_end - (t_first - fromSeconds(options_.start_s)))) +
                       " s of recording)");
    summary.messages += done;
  } while (options_.loop && !dds::ShutdownSignal::requested());
  if (options_.lossless) {
    for (auto& [name, p] : pubs) p->waitForAcknowledgments(std::chrono::seconds(30));
  }
  summary.interrupted = dds::ShutdownSignal::requested();
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - wall_start).count();
  return summary;
}

}  // namespace mcvio::components
