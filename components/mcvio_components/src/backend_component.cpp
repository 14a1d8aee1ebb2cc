#include "mcvio/components/backend_component.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <iostream>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "calibration_topics.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/dataset/rig_calibration_reader.hpp"
#include "mcvio/estimator/sliding_window_estimator.hpp"

namespace mcvio::components {
namespace {

using Clock = std::chrono::steady_clock;
using Imu = sensor_msgs::msg::dds_::Imu_;
using FeatureFrameMsg = mcvio_msgs::msg::dds_::FeatureFrame_;
using Odometry = nav_msgs::msg::dds_::Odometry_;

// The names the backend asks for; messages give the remapped ones (imu_topic, features_topic).
constexpr const char* kImuTopic = "/imu0";
constexpr const char* kFeaturesTopic = "/mcvio/features";

// Bad input can come at 200 Hz: say the first few, then one line per thousand.
bool worthLogging(std::size_t count) { return count <= 5 || count % 1000 == 0; }

}  // namespace

void BackendComponentOptions::validate() const {
  if (calibration_dir.empty()) {
    throw std::invalid_argument("backend options: calibration_dir is empty (the estimator needs the rig's extrinsics and IMU noise)");
  }
  if (world_frame.empty() || body_frame.empty() || secondary_frame.empty()) {
    throw std::invalid_argument("backend options: world_frame, body_frame and secondary_frame must not be empty");
  }
  if (world_frame == body_frame) throw std::invalid_argument("backend options: world_frame equals body_frame ('" + body_frame + "')");
  if (!(max_imu_wait_s >= 0)) throw std::invalid_argument("backend options: max_imu_wait_s must be >= 0");
  if (max_queued_frames == 0) throw std::invalid_argument("backend options: max_queued_frames must be >= 1");
  estimator.validate();
}

struct BackendComponent::Impl {
  struct PendingFrame {
    FeatureFrame frame;
    Clock::time_point arrival;
  };

  std::shared_ptr<dds::Node> node;
  BackendComponentOptions options;
  std::string imu_topic, features_topic;  ///< as remapped, for messages
  StereoRigCalibration rig;
  std::unique_ptr<estimator::SlidingWindowEstimator> estimator;

  std::unique_ptr<dds::Publisher<Odometry>> odometry_pub, secondary_pub;
  std::unique_ptr<dds::Publisher<nav_msgs::msg::dds_::Path_>> path_pub, secondary_path_pub;
  std::unique_ptr<dds::Publisher<tf2_msgs::msg::dds_::TFMessage_>> tf_pub, tf_static_pub;
  std::unique_ptr<dds::Publisher<sensor_msgs::msg::dds_::PointCloud2_>> landmarks_pub;
  std::unique_ptr<dds::Publisher<mcvio_msgs::msg::dds_::MotionConflict_>> conflict_pub;
  std::unique_ptr<dds::Subscription<Imu>> imu_sub;
  std::unique_ptr<dds::Subscription<FeatureFrameMsg>> features_sub;

  mutable std::mutex mutex;
  std::condition_variable cv, idle_cv;
  std::deque<ImuSample> imu;  // received, not yet given to the estimator
  std::deque<PendingFrame> frames;
  bool have_imu = false, have_frame = false;
  Timestamp last_imu_t = 0, last_frame_t = 0;
  bool flushing = false, busy = false;
  std::atomic<bool> running{true};
  BackendComponentStats stats;
  double latency_sum_ms = 0, cpu_sum_ms = 0;

  // Worker-thread state.
  std::deque<StampedPose> path, secondary_path;
  Eigen::Vector3d last_gyro = Eigen::Vector3d::Zero();
  estimator::EstimatorStatus last_status = estimator::EstimatorStatus::kNotInitialized;
  std::string last_not_initialized_message;
  std::size_t estimated_frames = 0;
  Timestamp warned_waiting_t = -1;  // the frame we said waits for IMU
  std::thread worker;

  Impl(std::shared_ptr<dds::Node> n, BackendComponentOptions o)
      : node(std::move(n)), options(std::move(o)) {
    options.validate();
    std::vector<std::string> calibration_warnings;
    rig = dataset::RigCalibrationReader::read(options.calibration_dir, &calibration_warnings);
    for (const auto& w : calibration_warnings) std::cerr << "mcvio backend: warning: " << w << "\n";
    detail::remapToCalibratedTopics(*node, rig, false, "backend");
    imu_topic = node->resolveTopic(kImuTopic);
    features_topic = node->resolveTopic(kFeaturesTopic);
    estimator = std::make_unique<estimator::SlidingWindowEstimator>(options.estimator, rig);

    const auto in_qos = options.lossless ? dds::QosProfile::lossless() : dds::QosProfile::sensorData();
    // Reliable outputs: RViz and `ros2 topic echo` ask for reliable by default, and a best-effort
    // reader matches a reliable writer too.
    const auto out_qos = options.lossless ? dds::QosProfile::lossless() : dds::QosProfile::defaults();
    auto tf_qos = dds::QosProfile::defaults();
    tf_qos.depth = 100;  // tf2's TransformBroadcaster
    odometry_pub = node->createPublisher<Odometry>("/mcvio/odometry", out_qos);
    secondary_pub = node->createPublisher<Odometry>("/mcvio/secondary_odometry", out_qos);
    path_pub = node->createPublisher<nav_msgs::msg::dds_::Path_>("/mcvio/path", dds::QosProfile::transientLocal(1));
    secondary_path_pub =
        node->createPublisher<nav_msgs::msg::dds_::Path_>("/mcvio/secondary_path", dds::QosProfile::transientLocal(1));
    tf_pub = node->createPublisher<tf2_msgs::msg::dds_::TFMessage_>("/tf", options.lossless ? out_qos : tf_qos);
    tf_static_pub = node->createPublisher<tf2_msgs::msg::dds_::TFMessage_>("/tf_static", dds::QosProfile::transientLocal(1));
    landmarks_pub = node->createPublisher<sensor_msgs::msg::dds_::PointCloud2_>("/mcvio/landmarks", out_qos);
    conflict_pub = node->createPublisher<mcvio_msgs::msg::dds_::MotionConflict_>("/mcvio/conflict", out_qos);

    const auto cam_name = [](const CameraCalibration& c, const char* fallback) { return c.name.empty() ? std::string(fallback) : c.name; };
    tf_static_pub->publish(toTfMessage({toTransformStamped(rig.cam0.T_BC, 0, options.body_frame, cam_name(rig.cam0, "cam0")),
                                        toTransformStamped(rig.cam1.T_BC, 0, options.body_frame, cam_name(rig.cam1, "cam1"))}));

    worker = std::thread([this] { run(); });
    imu_sub = node->createSubscription<Imu>(kImuTopic, in_qos, [this](const Imu& m) { onImu(m); });
    features_sub = node->createSubscription<FeatureFrameMsg>(kFeaturesTopic, in_qos, [this](const FeatureFrameMsg& m) { onFeatures(m); });
  }

  ~Impl() {
    imu_sub.reset();
    features_sub.reset();
    running = false;
    cv.notify_all();
    if (worker.joinable()) worker.join();
  }

  void onImu(const Imu& m) {
    const ImuSample s = fromImuMsg(m);
    std::lock_guard<std::mutex> lock(mutex);
    ++stats.imu_received;
    const char* why = nullptr;
    if (!s.gyro.allFinite() || !s.accel.allFinite()) {
      why = "non-finite angular velocity or acceleration";
    } else if (have_imu && s.t <= last_imu_t) {
      why = "stamp not after the previous sample's";
    }
    if (why) {
      ++stats.imu_rejected;
      if (worthLogging(stats.imu_rejected)) {
        std::cerr << "mcvio backend: " << imu_topic << " sample at " << s.t << " skipped: " << why << " (previous "
                  << last_imu_t << "; " << stats.imu_rejected << " skipped so far)\n";
      }
      return;
    }
    have_imu = true;
    last_imu_t = s.t;
    imu.push_back(s);
    if (!frames.empty()) cv.notify_one();
  }

  void onFeatures(const FeatureFrameMsg& m) {
    PendingFrame p{fromFeatureFrameMsg(m), Clock::now()};
    std::lock_guard<std::mutex> lock(mutex);
    ++stats.frames_received;
    if (have_frame && p.frame.t <= last_frame_t) {
      ++stats.frames_rejected;
      std::cerr << "mcvio backend: " << features_topic << " frame " << p.frame.frame_index << " at " << p.frame.t
                << " skipped: stamp not after the previous frame's (" << last_frame_t << ")\n";
      return;
    }
    if (p.frame.features.empty()) {
      // The estimator decides what such a frame means; say where it came from.
      std::cerr << "mcvio backend: " << features_topic << " frame " << p.frame.frame_index << " at " << p.frame.t
                << " has no features\n";
    }
    have_frame = true;
    last_frame_t = p.frame.t;
    if (!options.lossless && frames.size() >= options.max_queued_frames) {
      ++stats.frames_dropped;
      std::cerr << "mcvio backend: " << features_topic << " frame at " << frames.front().frame.t
                << " dropped: " << frames.size() << " frames wait for " << imu_topic << " (latest sample "
                << (have_imu ? std::to_string(last_imu_t) : std::string("none")) << ") or for the estimator\n";
      frames.pop_front();
    }
    frames.push_back(std::move(p));
    cv.notify_one();
  }

  // A frame may go once the IMU has reached its stamp (as `mcvio run` feeds it), on flush, or,
  // when losing data is allowed, after waiting max_imu_wait_s.
  bool frontReady(Clock::time_point now) const {
    if (frames.empty()) return false;
    const auto& f = frames.front();
    if (have_imu && last_imu_t >= f.frame.t) return true;
    if (flushing) return true;
    return !options.lossless && now - f.arrival >= std::chrono::duration<double>(options.max_imu_wait_s);
  }

  void run() {
    std::unique_lock<std::mutex> lock(mutex);
    while (true) {
      cv.wait_for(lock, std::chrono::milliseconds(20), [this] { return !running || frontReady(Clock::now()); });
      if (!running) return;
      if (!frontReady(Clock::now())) {
        if (flushing && frames.empty()) idle_cv.notify_all();
        if (!frames.empty() && frames.front().frame.t != warned_waiting_t &&
            Clock::now() - frames.front().arrival > std::chrono::seconds(5)) {
          warned_waiting_t = frames.front().frame.t;
          std::cerr << "mcvio backend: " << features_topic << " frame at " << warned_waiting_t << " waits for "
                    << imu_topic << " to reach its stamp (latest sample "
                    << (have_imu ? std::to_string(last_imu_t) : std::string("none")) << "); " << frames.size()
                    << " frames queued\n";
        }
        continue;
      }
      PendingFrame p = std::move(frames.front());
      frames.pop_front();
      std::vector<ImuSample> samples;
      while (!imu.empty() && imu.front().t <= p.frame.t) {
        samples.push_back(imu.front());
        imu.pop_front();
      }
      busy = true;
      lock.unlock();
      process(p, samples);
      lock.lock();
      busy = false;
      if (frames.empty()) idle_cv.notify_all();
    }
  }

  void process(const PendingFrame& p, const std::vector<ImuSample>& samples) {
    for (const auto& s : samples) estimator->addImu(s);
    if (!samples.empty()) last_gyro = samples.back().gyro;
    const auto e = estimator->addFrame(p.frame);
    const bool publish = e.status == estimator::EstimatorStatus::kTracking && e.frame_accepted;
    if (!e.frame_accepted && e.status != estimator::EstimatorStatus::kNotInitialized) {
      std::cerr << "mcvio backend: " << features_topic << " frame " << p.frame.frame_index << " at " << p.frame.t
                << " not used by the estimator: " << e.message << "\n";
    }
    switch (e.status) {
      case estimator::EstimatorStatus::kNotInitialized:
        if (e.message != last_not_initialized_message || last_status != e.status) {
          std::cerr << "mcvio backend: not initialised yet at " << e.t << (e.message.empty() ? "" : ": ") << e.message
                    << " (no pose is published until then)\n";
          last_not_initialized_message = e.message;
        }
        break;
      case estimator::EstimatorStatus::kReset:
        std::cerr << "mcvio backend: estimator reset at " << e.t << ": " << e.message
                  << " (poses resume once it is tracking again)\n";
        break;
      case estimator::EstimatorStatus::kTracking:
        if (last_status != estimator::EstimatorStatus::kTracking && publish) {
          std::cerr << "mcvio backend: tracking from " << e.t << "\n";
        } else if (e.frame_accepted && !e.message.empty()) {
          std::cerr << "mcvio backend: frame at " << e.t << ": " << e.message << "\n";
        }
        break;
    }
    last_status = e.status;

    if (publish) {
      const Eigen::Vector3d omega_B = last_gyro - e.bias.gyro;
      odometry_pub->publish(toOdometryMsg(e, omega_B, options.world_frame, options.body_frame));
      Eigen::Isometry3d T_WB = Eigen::Isometry3d::Identity();
      T_WB.linear() = e.q_WB.normalized().toRotationMatrix();
      T_WB.translation() = e.p_WB;
      tf_pub->publish(toTfMessage({toTransformStamped(T_WB, e.t, options.world_frame, options.body_frame)}));
      // The conflict window re-estimated earlier frames: the paths show the final estimates.
      path.push_back({e.t, e.p_WB, e.q_WB});
      estimator::applyPoseRevisions(&path, e.revised_poses);
      if (options.max_path_poses > 0 && path.size() > options.max_path_poses) path.pop_front();
      path_pub->publish(toPathMsg(std::vector<StampedPose>(path.begin(), path.end()), options.world_frame));
      conflict_pub->publish(toMotionConflictMsg(e, options.world_frame));
      if (e.conflict.secondary_valid) {
        secondary_pub->publish(toSecondaryOdometryMsg(e, options.world_frame, options.secondary_frame));
        secondary_path.push_back({e.t, e.conflict.p_WS, e.conflict.q_WS});
      }
      const bool secondary_revised = estimator::applyPoseRevisions(&secondary_path, e.revised_secondary);
      if (e.conflict.secondary_valid || secondary_revised) {
        if (options.max_path_poses > 0 && secondary_path.size() > options.max_path_poses) secondary_path.pop_front();
        secondary_path_pub->publish(
            toPathMsg(std::vector<StampedPose>(secondary_path.begin(), secondary_path.end()), options.world_frame));
      }
      ++estimated_frames;
      if (options.landmarks_every_n_frames > 0 && estimated_frames % options.landmarks_every_n_frames == 0) {
        landmarks_pub->publish(toPointCloud2Msg(estimator->landmarkPositions(), e.t, options.world_frame));
      }
    }

    const double latency_ms = std::chrono::duration<double, std::milli>(Clock::now() - p.arrival).count();
    std::lock_guard<std::mutex> lock(mutex);
    ++stats.frames_processed;
    stats.frames_not_accepted += !e.frame_accepted;
    stats.not_initialized += e.status == estimator::EstimatorStatus::kNotInitialized;
    stats.resets += e.status == estimator::EstimatorStatus::kReset;
    cpu_sum_ms += e.timings.cpu_total_ms;
    stats.estimator_cpu_ms_max = std::max(stats.estimator_cpu_ms_max, e.timings.cpu_total_ms);
    stats.estimator_cpu_ms_mean = cpu_sum_ms / static_cast<double>(stats.frames_processed);
    if (publish) {
      ++stats.poses_published;
      stats.conflict_frames += e.conflict.state == estimator::ConflictReport::State::kConflict;
      stats.secondary_published += e.conflict.secondary_valid;
      latency_sum_ms += latency_ms;
      stats.latency_ms_max = std::max(stats.latency_ms_max, latency_ms);
      stats.latency_ms_mean = latency_sum_ms / static_cast<double>(stats.poses_published);
    }
  }

  void flush() {
    std::unique_lock<std::mutex> lock(mutex);
    flushing = true;
    cv.notify_all();
    idle_cv.wait(lock, [this] { return (frames.empty() && !busy) || !running; });
    flushing = false;
  }
};

BackendComponent::BackendComponent(std::shared_ptr<dds::Node> node, BackendComponentOptions options)
    : impl_(std::make_unique<Impl>(std::move(node), std::move(options))) {}

BackendComponent::~BackendComponent() = default;

void BackendComponent::flush() { impl_->flush(); }

BackendComponentStats BackendComponent::stats() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->stats;
}

}  // namespace mcvio::components
