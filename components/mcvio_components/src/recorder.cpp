#include "mcvio/components/recorder.hpp"

#include <chrono>
#include <cstring>
#include <iostream>

#include "mcvio/interfaces/message_registry.hpp"

namespace mcvio::components {
namespace {

// Reliable publishers get a keep-all reader (compatibleReaderQos): their history flows to the bag
// without loss.
// rosbag2's offered_qos_profiles: one entry per publisher. Discovery tells reliability and
// durability; history and depth are not announced, so they are written as "unknown" (3) / 0.
std::string offeredQosYaml(const dds::DiscoveredTopic& t) {
  std::string y;
  for (const auto& q : t.publisher_qos) {
    std::string entry = q.toRosbag2Yaml();
    entry.replace(0, entry.find('\n'), "history: 3");
    const auto depth = entry.find("depth: ");
    entry.replace(depth, entry.find('\n', depth) - depth, "depth: 0");
    y += "- " + entry;
  }
  return y;
}

// `regex`: the options' regex compiled (nullptr when they have none).
bool selectsTopic(const RecorderOptions& o, const std::regex* regex, const std::string& topic) {
  if (o.all) return true;
  for (const auto& name : o.topics) {
    if (name == topic || "/" + name == topic) return true;
  }
  return regex != nullptr && std::regex_search(topic, *regex);
}

}  // namespace

void RecorderOptions::validate() const {
  if (topics.empty() && !all && regex.empty()) {
    throw std::invalid_argument("record: name topics, or give --all or --regex");
  }
  if (!regex.empty()) {
    try {
      std::regex r(regex);
    } catch (const std::regex_error& e) {
      throw std::invalid_argument("record: --regex '" + regex + "' is not a valid regular expression: " + e.what());
    }
  }
  if (!(discovery_period_s > 0)) throw std::invalid_argument("record: discovery period must be > 0");
  bag.validate();
}

Recorder::Recorder(std::shared_ptr<dds::Node> node, dds::GraphMonitor& monitor, const std::string& bag_dir,
                   RecorderOptions options)
    : node_(std::move(node)), monitor_(monitor), options_(std::move(options)) {
  options_.validate();
  if (!options_.regex.empty()) regex_ = std::regex(options_.regex);
  writer_ = std::make_unique<bag::BagWriter>(bag_dir, options_.bag);
}

Recorder::~Recorder() {
  if (running_) stop();
}

bool RecorderOptions::selects(const std::string& topic) const {
  if (regex.empty()) return selectsTopic(*this, nullptr, topic);
  const std::regex compiled(regex);
  return selectsTopic(*this, &compiled, topic);
}

bool Recorder::selected(const dds::DiscoveredTopic& t) const {
  if (!t.is_ros || t.publishers == 0) return false;
  return selectsTopic(options_, options_.regex.empty() ? nullptr : &regex_, t.name);
}

void Recorder::start() {
  running_ = true;
  writer_thread_ = std::thread([this] { writerLoop(); });
  discovery_thread_ = std::thread([this] { discoveryLoop(); });
}

void Recorder::discoveryLoop() {
  // Entities are created here, not in the discovery callback: Fast DDS must not be re-entered
  // from its own discovery thread.
  while (running_) {
    for (const auto& t : monitor_.topics()) {
      bool known;
      {
        std::lock_guard<std::mutex> lock(subs_mutex_);
        known = subs_.count(t.name) > 0;
      }
      if (!known && selected(t)) subscribe(t);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(options_.discovery_period_s * 1000)));
  }
}

void Recorder::subscribe(const dds::DiscoveredTopic& t) {
  bag::TopicInfo info;
  info.name = t.name;
  info.type = t.type;
  info.offered_qos_profiles = offeredQosYaml(t);
  info.type_description_hash = t.type_hash;
  // Types we know carry their definition; others are still recorded, as opaque CDR.
  if (const auto* d = interfaces::MessageRegistry::find(t.type)) {
    info.message_definition = std::string(d->full_definition);
    if (info.type_description_hash.empty()) info.type_description_hash = std::string(d->type_hash);
  }
  // Types that start with a std_msgs/Header (Image, Imu, Odometry, ...) have their stamp at a
  // fixed place: CDR header (4) + sec (4) + nanosec (4). That stamp is stored as publish time.
  bool stamped = false;
  if (const auto* d = interfaces::MessageRegistry::find(t.type)) {
    const std::string_view text = d->text;
    std::size_t pos = 0;
    while (pos < text.size()) {
      auto end = text.find('\n', pos);
      std::string_view line = text.substr(pos, end == std::string_view::npos ? std::string_view::npos : end - pos);
      pos = end == std::string_view::npos ? text.size() : end + 1;
      const auto first = line.find_first_not_of(" \t");
      if (first == std::string_view::npos || line[first] == '#') continue;
      if (line.find('=') != std::string_view::npos && line.find("<=") == std::string_view::npos) continue;  // constant
      stamped = line.substr(first).rfind("std_msgs/Header ", 0) == 0;
      break;
    }
  }
  std::size_t index;
  {
    std::lock_guard<std::mutex> lock(writer_mutex_);
    index = writer_->addTopic(info);
    topic_names_[index] = t.name;
  }
  auto sub = std::make_unique<dds::GenericSubscription>(
      *node_, t.name, t.dds_type, t.type_hash, t.compatibleReaderQos(/*keep_all_when_reliable=*/true), [this, index, stamped](const dds::ReceivedPayload& p) {
        std::int64_t header_time = p.source_time_ns;
        const auto& b = *p.payload;
        if (stamped && b.size() >= 12 && b[1] == 0x01) {  // little-endian plain CDR
          std::int32_t sec;
          std::uint32_t nsec;
          std::memcpy(&sec, b.data() + 4, 4);
          std::memcpy(&nsec, b.data() + 8, 4);
          header_time = static_cast<std::int64_t>(sec) * 1000000000 + nsec;
        }
        {
          std::lock_guard<std::mutex> lock(queue_mutex_);
          queue_.push_back(Queued{index, p.receive_time_ns, header_time, *p.payload});
        }
        queue_cv_.notify_one();
      });
  std::lock_guard<std::mutex> lock(subs_mutex_);
  subs_[t.name] = std::move(sub);
  std::cerr << "mcvio record: recording " << t.name << " [" << t.type << "]\n";
}

void Recorder::writerLoop() {
  // A chunk is only safe from kill -9 once it is complete on disk: flush the open one at least
  // every second, so a killed recorder loses at most about the last second.
  using Clock = std::chrono::steady_clock;
  auto last_flush = Clock::now();
  bool dirty = false;
  std::unique_lock<std::mutex> lock(queue_mutex_);
  while (true) {
    queue_cv_.wait_for(lock, std::chrono::milliseconds(200), [this] { return !queue_.empty() || !running_; });
    if (queue_.empty() && !running_) break;
    while (!queue_.empty()) {
      Queued q = std::move(queue_.front());
      queue_.pop_front();
      bag::BagMessage m;
      m.log_time = q.log_time;
      m.publish_time = q.publish_time > 0 ? q.publish_time : q.log_time;
      m.data = std::move(q.data);
      // Keep DDS threads queueing while the (possibly compressing) write runs.
      lock.unlock();
      {
        std::lock_guard<std::mutex> wlock(writer_mutex_);
        m.topic = topic_names_.at(q.topic_index);
        summary_.bytes += m.data.size();
        ++summary_.messages_per_topic[m.topic];
        writer_->write(m);
      }
      ++written_;
      dirty = true;
      lock.lock();
      if (Clock::now() - last_flush > std::chrono::seconds(1)) break;
    }
    if (dirty && Clock::now() - last_flush > std::chrono::seconds(1)) {
      lock.unlock();
      {
        std::lock_guard<std::mutex> wlock(writer_mutex_);
        writer_->flush();
      }
      lock.lock();
      last_flush = Clock::now();
      dirty = false;
    }
  }
}

RecordingSummary Recorder::stop() {
  if (!running_) return summary_;
  running_ = false;
  if (discovery_thread_.joinable()) discovery_thread_.join();
  {
    std::lock_guard<std::mutex> lock(subs_mutex_);
    subs_.clear();  // no more samples after this
  }
  queue_cv_.notify_all();
  if (writer_thread_.joinable()) writer_thread_.join();
  std::lock_guard<std::mutex> wlock(writer_mutex_);
  writer_->close();
  summary_.messages = written_.load();
  return summary_;
}

std::vector<std::string> Recorder::recordedTopics() const {
  std::lock_guard<std::mutex> lock(subs_mutex_);
  std::vector<std::string> v;
  for (const auto& [n, s] : subs_) v.push_back(n);
  return v;
}

}  // namespace mcvio::components
