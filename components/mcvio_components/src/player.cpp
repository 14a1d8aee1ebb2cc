#include "mcvio/components/player.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <stdexcept>
#include <thread>

#include "mcvio/components/playback_pacer.hpp"
#include "mcvio/components/reader_wait.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/core/progress_bar.hpp"
#include "mcvio/dds/shutdown_signal.hpp"

namespace mcvio::components {

using Image = sensor_msgs::msg::dds_::Image_;
using Imu = sensor_msgs::msg::dds_::Imu_;
using CameraInfo = sensor_msgs::msg::dds_::CameraInfo_;
using Odometry = nav_msgs::msg::dds_::Odometry_;

struct Player::Publishers {
  std::unique_ptr<dds::Publisher<Image>> image[2];
  std::unique_ptr<dds::Publisher<CameraInfo>> info[2];
  std::unique_ptr<dds::Publisher<Imu>> imu;
  std::unique_ptr<dds::Publisher<Odometry>> ground_truth;
  std::vector<dds::WriterEndpoint*> all() const {
    std::vector<dds::WriterEndpoint*> v = {image[0].get(), image[1].get(), info[0].get(), info[1].get(), imu.get()};
    if (ground_truth) v.push_back(ground_truth.get());
    return v;
  }
};

void PlayerOptions::validate() const {
  if (!(rate > 0.0)) throw std::invalid_argument("player: rate must be > 0, got " + std::to_string(rate));
  if (!(wait_for_readers_s >= 0 && wait_for_readers_s <= 86400)) throw std::invalid_argument("player: wait_for_readers_s must be in [0, 86400]");
  if (min_readers < 0) throw std::invalid_argument("player: min_readers must be >= 0");
  if (!(settle_s >= 0 && settle_s <= 60)) throw std::invalid_argument("player: settle_s must be in [0, 60]");
  if (!(start_s >= 0) || !(duration_s >= 0)) throw std::invalid_argument("player: start_s and duration_s must be >= 0");
  if (!(max_gap_s >= 0)) {
    throw std::invalid_argument("player: max_gap_s must be >= 0 (0 = never shorten a gap), got " + std::to_string(max_gap_s));
  }
}

Player::Player(std::shared_ptr<dds::Node> node, const dataset::EurocDataset& data, PlayerOptions options)
    : node_(std::move(node)), data_(data), options_(options), pubs_(std::make_unique<Publishers>()) {
  options_.validate();
  const auto sensor = options_.lossless ? dds::QosProfile::lossless() : dds::QosProfile::sensorData();
  const auto reliable = options_.lossless ? dds::QosProfile::lossless() : dds::QosProfile::defaults();
  for (int c = 0; c < 2; ++c) {
    const std::string cam = "/cam" + std::to_string(c);
    pubs_->image[c] = node_->createPublisher<Image>(cam + "/image_raw", sensor);
    pubs_->info[c] = node_->createPublisher<CameraInfo>(cam + "/camera_info", reliable);
  }
  pubs_->imu = node_->createPublisher<Imu>("/imu0", sensor);
  if (!data_.groundTruth().empty()) {
    pubs_->ground_truth = node_->createPublisher<Odometry>("/ground_truth/odometry", reliable);
  }
}

Player::~Player() = default;

PlaybackSummary Player::run() {
  using Clock = std::chrono::steady_clock;
  PlaybackSummary summary;
  // One time line of frames, IMU samples and ground truth, in time order (frames first on ties,
  // as a camera driver's image and the IMU sample of the same instant).
  enum Kind : std::uint8_t { kFrame, kImu, kGroundTruth };
  struct Event {
    Timestamp t;
    Kind kind;
    std::size_t index;
  };
  std::vector<Event> events;
  for (std::size_t i = 0; i < data_.stereoFrames().size(); ++i) events.push_back({data_.stereoFrames()[i].t, kFrame, i});
  for (std::size_t i = 0; i < data_.imu().size(); ++i) events.push_back({data_.imu()[i].t, kImu, i});
  for (std::size_t i = 0; i < data_.groundTruth().size(); ++i) events.push_back({data_.groundTruth()[i].t, kGroundTruth, i});
  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
    return a.t != b.t ? a.t < b.t : a.kind < b.kind;
  });
  if (events.empty()) throw InputError("player: " + data_.root() + " has no frames, IMU or ground truth to play");
  const Timestamp t_first = events.front().t + fromSeconds(options_.start_s);
  const Timestamp t_last = options_.duration_s > 0 ? t_first + fromSeconds(options_.duration_s) : events.back().t;
  const auto begin = std::lower_bound(events.begin(), events.end(), t_first, [](const Event& e, Timestamp t) { return e.t < t; });
  const auto end = std::upper_bound(events.begin(), events.end(), t_last, [](Timestamp t, const Event& e) { return t < e.t; });
  const std::size_t total = static_cast<std::size_t>(end - begin);
  if (total == 0 && options_.start_s > 0)
    throw InputError("player: --start " + std::to_string(options_.start_s) + " s is past the end of " + data_.root() +
                     " (" + std::to_string(toSeconds(events.back().t - events.front().t)) + " s of data)");
  if (options_.wait_for_readers_s > 0 && options_.min_readers > 0) {
    std::vector<ReaderDemand> demands;
    for (auto* p : pubs_->all())
      demands.push_back({p, options_.min_readers + (options_.extra_readers ? options_.extra_readers(p->topic()) : 0)});
    const auto wait = waitForReaders(demands, options_.wait_for_readers_s, options_.progress, "mcvio play");
    if (wait.interrupted) {
      summary.interrupted = true;
      return summary;
    }
    if (!wait.topics_without_readers.empty()) {
      if (options_.lossless)
        throw std::runtime_error("player: no reader of " + wait.topics_without_readers.front() + " within " +
                                 std::to_string(options_.wait_for_readers_s) +
                                 " s; lossless playback needs its readers before it starts");
      if (options_.progress)
        std::cerr << "mcvio play: no reader yet of " << wait.topics_without_readers.size() << " of " << demands.size()
                  << " topics (" << wait.topics_without_readers.front() << (wait.topics_without_readers.size() > 1 ? ", ..." : "")
                  << "); playing anyway\n";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(options_.settle_s * 1000)));
  }

  const auto wall_start = Clock::now();
  do {
    ProgressBar bar("play", total, options_.progress);
    const auto pass_start = Clock::now();
    std::size_t done = 0;
    PlaybackPacer pacer(t_first, options_.rate, options_.max_gap_s);
    for (auto it = begin; it != end && !dds::ShutdownSignal::requested(); ++it, ++done) {
      if (!options_.lossless) {
        // The events are sorted, so only gaps need handling here.
        const auto step = pacer.next(it->t);
        if (step.skipped_s > 0) {
          const dds::WriterEndpoint* const by_kind[] = {pubs_->image[0].get(), pubs_->imu.get(), pubs_->ground_truth.get()};
          std::cerr << "mcvio play: warning: " << data_.root() << ": topic " << by_kind[it->kind]->topic() << ", event "
                    << done + 1 << " of " << total << " at " << it->t << " ns: "
                    << PlaybackPacer::describe(step, options_.max_gap_s) << "\n";
          ++summary.shortened_gaps;
          summary.skipped_gap_seconds += step.skipped_s;
        }
        std::this_thread::sleep_until(pass_start + step.wall_offset);
      }
      bool ok = true;
      switch (it->kind) {
        case kFrame: {
          const auto& f = data_.stereoFrames()[it->index];
          cv::Mat img[2];
          try {
            img[0] = data_.loadImage(f, 0);
            img[1] = data_.loadImage(f, 1);
          } catch (const InputError& e) {
            std::cerr << "mcvio play: skipping frame at " << f.t << ": " << e.what() << "\n";
            ++summary.skipped_frames;
            continue;
          }
          for (int c = 0; c < 2; ++c) {
            ok = ok && pubs_->info[c]->publish(toCameraInfoMsg(data_.calibration().camera(c), f.t));
            ok = ok && pubs_->image[c]->publish(toImageMsg(img[c], c == 0 ? f.t : f.t_cam1, "cam" + std::to_string(c)));
          }
          ++summary.frames;
          break;
        }
        case kImu:
          ok = pubs_->imu->publish(toImuMsg(data_.imu()[it->index], "imu0"));
          ++summary.imu_samples;
          break;
        case kGroundTruth:
          ok = pubs_->ground_truth->publish(toOdometryMsg(data_.groundTruth()[it->index], "world", "imu0"));
          ++summary.ground_truth;
          break;
      }
      if (!ok) {
        throw std::runtime_error("player: a lossless reader stopped taking samples for 60 s; stopping with " +
                                 std::to_string(done) + " of " + std::to_string(total) + " published");
      }
      if (done % 20 == 0) {
        const double data_s = toSeconds(it->t - t_first);
        const double wall_s = std::chrono::duration<double>(Clock::now() - pass_start).count();
        char detail[96];
        std::snprintf(detail, sizeof detail, "%.1f s of data, %.1fx real time", data_s, wall_s > 0 ? data_s / wall_s : 0.0);
        bar.update(done, detail);
      }
    }
    bar.finish();
  } while (options_.loop && !dds::ShutdownSignal::requested());
  summary.interrupted = dds::ShutdownSignal::requested();
  summary.messages = summary.frames * 4 + summary.imu_samples + summary.ground_truth;
  if (options_.lossless) {
    for (auto* p : pubs_->all()) p->waitForAcknowledgments(std::chrono::seconds(30));
  }
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - wall_start).count();
  summary.data_seconds = toSeconds(t_last - t_first);
  return summary;
}

}  // namespace mcvio::components
