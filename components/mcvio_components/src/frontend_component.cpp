#include "mcvio/components/frontend_component.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <stdexcept>

#include "calibration_topics.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/rig_calibration_reader.hpp"
#include "mcvio/dataset/sensor_image.hpp"
#include "mcvio/frontend/track_drawer.hpp"

namespace mcvio::components {
namespace {

using Image = sensor_msgs::msg::dds_::Image_;
using CompressedImage = sensor_msgs::msg::dds_::CompressedImage_;
using Imu = sensor_msgs::msg::dds_::Imu_;
using FeatureFrameMsg = mcvio_msgs::msg::dds_::FeatureFrame_;

// The grey image the tracker takes, from any common encoding; empty with a reason otherwise.
cv::Mat imageOf(const Image& msg, std::string* why) {
  return dataset::greyImageOf({msg.encoding(), msg.width(), msg.height(), msg.step(), msg.is_bigendian() != 0,
                               msg.data().data(), msg.data().size()},
                              why);
}
cv::Mat imageOf(const CompressedImage& msg, std::string* why) {
  return dataset::greyImageOfCompressed(msg.format(), msg.data().data(), msg.data().size(), why);
}

}  // namespace

struct FrontendComponent::Impl {
  std::shared_ptr<dds::Node> node;
  FrontendComponentOptions options;
  frontend::FeatureTracker tracker;
  std::unique_ptr<dds::Publisher<FeatureFrameMsg>> features_pub;
  std::unique_ptr<dds::Publisher<Image>> tracks_pub;
  std::unique_ptr<dds::Subscription<Image>> left_sub, right_sub;
  std::unique_ptr<dds::Subscription<CompressedImage>> left_compressed_sub, right_compressed_sub;
  std::unique_ptr<dds::Subscription<Imu>> imu_sub;
  std::string image_topic[2];  ///< as remapped, for messages
  Timestamp camera_time_offset_ns = 0;  ///< the calibration's: image stamp -> IMU clock

  mutable std::mutex mutex;
  std::condition_variable cv;
  std::map<Timestamp, cv::Mat> left, right;  // waiting for their partner
  std::deque<frontend::StereoInput> queue;
  std::vector<ImuSample> imu;  // not yet handed to the tracker
  Timestamp last_imu_t = 0;
  bool have_imu = false;
  FrontendComponentStats stats;
  std::atomic<bool> running{true};
  std::thread worker;

  explicit Impl(std::shared_ptr<dds::Node> n, FrontendComponentOptions o)
      : node(std::move(n)), options(std::move(o)), tracker(options.tracker) {
    options.validate();
    if (!options.calibration_dir.empty()) {
      std::vector<std::string> calibration_warnings;
      const auto rig = dataset::RigCalibrationReader::read(options.calibration_dir, &calibration_warnings);
      for (const auto& w : calibration_warnings) std::cerr << "mcvio frontend: warning: " << w << "\n";
      camera_time_offset_ns = rig.camera_time_offset_ns;
      tracker.setCalibration(rig);
      detail::remapToCalibratedTopics(*node, rig, true, "frontend");
    } else {
      std::cerr << "mcvio frontend: no --calib given: frames are skipped until a calibration is set "
                   "(camera_info has no stereo extrinsics)\n";
    }
    image_topic[0] = node->resolveTopic("/cam0/image_raw");
    image_topic[1] = node->resolveTopic("/cam1/image_raw");
    const auto in_qos = options.lossless ? dds::QosProfile::lossless() : dds::QosProfile::sensorData();
    const auto out_qos = options.lossless ? dds::QosProfile::lossless() : dds::QosProfile::defaults();
    features_pub = node->createPublisher<FeatureFrameMsg>("/mcvio/features", out_qos);
    if (options.publish_tracks_image) tracks_pub = node->createPublisher<Image>("/mcvio/tracks_image", dds::QosProfile::sensorData());
    worker = std::thread([this] { run(); });
    if (options.image_transport == "compressed") {
      // image_transport's naming: the compressed stream of base topic B is B/compressed.
      for (auto& name : image_topic) name += "/compressed";
      left_compressed_sub = node->createSubscription<CompressedImage>(image_topic[0], in_qos, [this](const CompressedImage& m) { onImage(m, 0); });
      right_compressed_sub = node->createSubscription<CompressedImage>(image_topic[1], in_qos, [this](const CompressedImage& m) { onImage(m, 1); });
    } else {
      left_sub = node->createSubscription<Image>("/cam0/image_raw", in_qos, [this](const Image& m) { onImage(m, 0); });
      right_sub = node->createSubscription<Image>("/cam1/image_raw", in_qos, [this](const Image& m) { onImage(m, 1); });
    }
    imu_sub = node->createSubscription<Imu>("/imu0", in_qos, [this](const Imu& m) { onImu(m); });
  }

  ~Impl() {
    left_sub.reset();
    right_sub.reset();
    left_compressed_sub.reset();
    right_compressed_sub.reset();
    imu_sub.reset();
    running = false;
    cv.notify_all();
    if (worker.joinable()) worker.join();
  }

  void onImu(const Imu& m) {
    const ImuSample s = fromImuMsg(m);
    std::lock_guard<std::mutex> lock(mutex);
    imu.push_back(s);  // the tracker ignores non-finite or old samples and counts them
    if (!have_imu || s.t > last_imu_t) last_imu_t = s.t;
    have_imu = true;
    cv.notify_one();
  }

  template <class Msg>
  void onImage(const Msg& m, int camera) {
    std::string why;
    cv::Mat img = imageOf(m, &why);
    const Timestamp t = stampOf(m.header());
    std::lock_guard<std::mutex> lock(mutex);
    if (img.empty()) {
      ++stats.bad_images;
      std::cerr << "mcvio frontend: " << image_topic[camera] << " at " << t << " skipped: " << why << "\n";
      return;
    }
    auto& mine = camera == 0 ? left : right;
    auto& other = camera == 0 ? right : left;
    auto partner = other.lower_bound(t - options.stereo_tolerance_ns);
    if (partner != other.end() && partner->first <= t + options.stereo_tolerance_ns) {
      frontend::StereoInput in;
      in.t = camera == 0 ? t : partner->first;
      in.left = camera == 0 ? img : partner->second;
      in.right = camera == 0 ? partner->second : img;
      // Older unpaired images will never find a partner now.
      for (auto it = other.begin(); it != partner;) { ++stats.unpaired_images; it = other.erase(it); }
      other.erase(partner);
      for (auto it = mine.begin(); it != mine.end() && it->first < t;) { ++stats.unpaired_images; it = mine.erase(it); }
      ++stats.pairs_received;
      if (!options.lossless && queue.size() >= options.max_queued_pairs) {
        ++stats.pairs_dropped;
        std::cerr << "mcvio frontend: tracker behind, dropping the pair at " << queue.front().t << "\n";
        queue.pop_front();  // its IMU stays in the buffer for the next pair
      }
      queue.push_back(std::move(in));
      cv.notify_one();
    } else {
      mine[t] = img;
      if (mine.size() > 10) {  // a partner that never comes (lost frame): do not grow forever
        ++stats.unpaired_images;
        mine.erase(mine.begin());
      }
    }
  }

  void run() {
    while (true) {
      frontend::StereoInput in;
      {
        std::unique_lock<std::mutex> lock(mutex);
        cv.wait(lock, [this] { return !queue.empty() || !running; });
        if (queue.empty()) return;
        // The tracker gets the IMU through the first sample at or after the frame time, as
        // `mcvio run` hands it (the player publishes a frame before the IMU of the same instant).
        // Lossless: wait for that sample, at most a second (the end of a stream).
        const Timestamp t = queue.front().t + camera_time_offset_ns;  // on the IMU's clock
        if (options.lossless)
          cv.wait_for(lock, std::chrono::seconds(1), [&] { return (have_imu && last_imu_t >= t) || !running; });
        if (!running) return;
        in = std::move(queue.front());
        queue.pop_front();
        auto split = std::find_if(imu.begin(), imu.end(), [&](const ImuSample& s) { return s.t >= t; });
        if (split != imu.end()) ++split;
        in.imu.assign(imu.begin(), split);
        imu.erase(imu.begin(), split);
      }
      const auto result = tracker.track(in);
      std::lock_guard<std::mutex> lock(mutex);
      if (!result.ok()) {
        ++stats.frames_skipped;
        std::cerr << "mcvio frontend: frame " << in.t << " skipped (" << frontend::toString(result.status)
                  << "): " << result.message << "\n";
        continue;
      }
      features_pub->publish(toFeatureFrameMsg(result.features));
      ++stats.frames_published;
      if (tracks_pub) {
        cv::Mat rgb = frontend::drawTracks(in.left, tracker.trackHistories(), tracker.mask(0));
        Image msg;
        msg.header(makeHeader(in.t, "cam0"));
        msg.height(static_cast<std::uint32_t>(rgb.rows));
        msg.width(static_cast<std::uint32_t>(rgb.cols));
        msg.encoding("rgb8");
        msg.step(static_cast<std::uint32_t>(rgb.cols * 3));
        msg.data().assign(rgb.data, rgb.data + rgb.total() * 3);
        tracks_pub->publish(msg);
      }
    }
  }
};

void FrontendComponentOptions::validate() const {
  if (image_transport != "raw" && image_transport != "compressed")
    throw std::invalid_argument("frontend: image_transport '" + image_transport + "' is not raw or compressed");
  if (max_queued_pairs == 0) throw std::invalid_argument("frontend: max_queued_pairs must be at least 1");
}

FrontendComponent::FrontendComponent(std::shared_ptr<dds::Node> node, FrontendComponentOptions options)
    : impl_(std::make_unique<Impl>(std::move(node), std::move(options))) {}

FrontendComponent::~FrontendComponent() = default;

std::vector<std::string> FrontendComponent::imageTopics() const { return {impl_->image_topic[0], impl_->image_topic[1]}; }

FrontendComponentStats FrontendComponent::stats() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->stats;
}

}  // namespace mcvio::components
