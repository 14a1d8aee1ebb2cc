#include "mcvio/estimator/sliding_window_estimator.hpp"

#include <algorithm>
#include <chrono>
#include <time.h>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

#include <ceres/ceres.h>
#include <spdlog/spdlog.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/estimator/anchor_observation_factor.hpp"
#include "mcvio/estimator/imu_factor.hpp"
#include "mcvio/estimator/landmark_registration.hpp"
#include "mcvio/estimator/marginalizer.hpp"
#include "mcvio/estimator/model_agreement_stop.hpp"
#include "mcvio/estimator/relative_rotation_factor.hpp"
#include "mcvio/estimator/reprojection_factor.hpp"
#include "mcvio/estimator/so3.hpp"
#include "mcvio/estimator/zero_velocity_factor.hpp"

namespace mcvio::estimator {

struct SlidingWindowEstimator::ProblemHolder {
  std::unique_ptr<ceres::Problem> problem;
};

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Thread CPU time [ms]: on a shared machine it tells the estimator's own cost apart from waiting.
double threadCpuMs() {
  timespec c{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c);
  return static_cast<double>(c.tv_sec) * 1e3 + static_cast<double>(c.tv_nsec) * 1e-6;
}

double yawOf(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));
}

Eigen::Vector3d stdDev(const std::vector<Eigen::Vector3d>& v) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), var = Eigen::Vector3d::Zero();
  for (const auto& x : v) mean += x;
  mean /= static_cast<double>(v.size());
  for (const auto& x : v) var += (x - mean).cwiseAbs2();
  return (var / static_cast<double>(v.size())).cwiseSqrt();
}

constexpr const char* kLog = "[mcvio_estimator] ";

}  // namespace

const char* toString(EstimatorStatus status) {
  switch (status) {
    case EstimatorStatus::kNotInitialized:
      return "not_initialized";
    case EstimatorStatus::kTracking:
      return "tracking";
    case EstimatorStatus::kReset:
      return "reset";
  }
  return "unknown";
}

const char* toString(ConflictReport::State state) {
  switch (state) {
    case ConflictReport::State::kNone:
      return "none";
    case ConflictReport::State::kSuspected:
      return "suspected";
    case ConflictReport::State::kConflict:
      return "conflict";
  }
  return "unknown";
}

SlidingWindowEstimator::ResidualRecord::ResidualRecord(ceres::CostFunction* cost_function,
                                                       ceres::LossFunction* loss_function,
                                                       std::initializer_list<double*> blocks, ResidualKind residual_kind)
    : cost(cost_function), loss(loss_function), kind(residual_kind), num_params(static_cast<int>(blocks.size())) {
  if (blocks.size() > inline_params.size()) throw std::logic_error("ResidualRecord: too many parameter blocks");
  std::copy(blocks.begin(), blocks.end(), inline_params.begin());
}

SlidingWindowEstimator::ResidualRecord::ResidualRecord(ceres::CostFunction* cost_function,
                                                       const std::vector<double*>& blocks)
    : cost(cost_function), loss(nullptr), kind(ResidualKind::kPrior), num_params(static_cast<int>(blocks.size())) {
  if (num_params <= kInlineParams)
    std::copy(blocks.begin(), blocks.end(), inline_params.begin());
  else
    prior_params = blocks;
}

SlidingWindowEstimator::SlidingWindowEstimator(const EstimatorOptions& options, const Eigen::Isometry3d& T_BC0,
                                               const Eigen::Isometry3d& T_BC1, double focal_length_px,
                                               const ImuNoiseParams& imu_noise)
    : options_(options), T_BC0_(T_BC0), T_BC1_(T_BC1), focal_px_(focal_length_px), imu_noise_(imu_noise) {
  options_.validate();
  if (!(focal_length_px > 0) || !std::isfinite(focal_length_px))
    throw InputError("SlidingWindowEstimator: focal length must be positive");
  T_C1C0_ = T_BC1_.inverse() * T_BC0_;
  imu_noise_.gyroscope_noise_density *= options_.imu_noise_inflation;
  imu_noise_.accelerometer_noise_density *= options_.imu_noise_inflation;
  imu_noise_.gyroscope_random_walk *= options_.imu_random_walk_inflation;
  imu_noise_.accelerometer_random_walk *= options_.imu_random_walk_inflation;
  gravity_ = Eigen::Vector3d(0, 0, -options_.gravity_magnitude);
  const double scale = options_.robust_loss_scale_px / options_.observation_sigma_px;
  if (options_.robust_loss == RobustLoss::kHuber)
    loss_ = std::make_unique<ceres::HuberLoss>(scale);
  else if (options_.robust_loss == RobustLoss::kCauchy)
    loss_ = std::make_unique<ceres::CauchyLoss>(scale);
  bias_hold_manifold_ = std::make_unique<ceres::SubsetManifold>(9, std::vector<int>{3, 4, 5, 6, 7, 8});
  conflict::RigGeometry geometry;
  geometry.T_BC0 = T_BC0_;
  geometry.T_BC1 = T_BC1_;
  geometry.focal_px = focal_px_;
  monitor_ = std::make_unique<MotionConflictMonitor>(options_.conflict, geometry, imu_noise_, gravity_,
                                                     options_.min_depth_m, options_.max_depth_m);
  // Both windows, the frame being added and some slack.
  frame_storage_.resize(static_cast<std::size_t>(options_.imu_window_size + options_.keyframe_window_size + 4));
  for (auto it = frame_storage_.rbegin(); it != frame_storage_.rend(); ++it) free_frames_.push_back(&*it);
}

void SlidingWindowEstimator::FrameRecycler::operator()(Frame* frame) const {
  if (owner == nullptr) {
    delete frame;
    return;
  }
  *frame = Frame{};
  owner->free_frames_.push_back(frame);
}

SlidingWindowEstimator::FramePtr SlidingWindowEstimator::makeFrame() {
  if (free_frames_.empty()) return FramePtr(new Frame, FrameRecycler{nullptr});
  Frame* f = free_frames_.back();
  free_frames_.pop_back();
  return FramePtr(f, FrameRecycler{this});
}

void SlidingWindowEstimator::placeLandmark(Landmark& lm) {
  lm.slot = landmark_params_.acquire();
  if (landmark_params_.moved())
    for (auto& [track, other] : landmarks_) other.param = landmark_params_.data(other.slot);
  lm.param = landmark_params_.data(lm.slot);
}

void SlidingWindowEstimator::clearLandmarks() {
  landmarks_.clear();
  landmark_params_.clear();
}

SlidingWindowEstimator::SlidingWindowEstimator(const EstimatorOptions& options, const StereoRigCalibration& rig)
    : SlidingWindowEstimator(options, rig.cam0.T_BC, rig.cam1.T_BC,
                             rig.cam0.model.focalLengthAtCentre(), rig.imu.noise) {
  cameras_ = std::array<CameraModel, 2>{rig.cam0.model, rig.cam1.model};
}

std::optional<Eigen::Matrix2d> SlidingWindowEstimator::localPixelJacobian(int camera,
                                                                          const Eigen::Vector2d& normalised) const {
  if (!cameras_) return std::nullopt;
  const CameraModel& lens = (*cameras_)[static_cast<std::size_t>(camera)];
  if (!usesLocalPixelScale(options_.pixel_scale, lens.distortionModel())) return std::nullopt;
  const Eigen::Matrix2d J = lens.pixelJacobianAt(normalised);
  if (!J.allFinite() || !(std::abs(J.determinant()) > 0.0)) return std::nullopt;
  return J;
}

SlidingWindowEstimator::~SlidingWindowEstimator() {
  // The problem refers to the cost functions; drop it first.
  records_.clear();
  problem_.reset();
}

bool SlidingWindowEstimator::addImu(const ImuSample& sample) {
  std::string msg;
  const auto res = imu_.add(sample, options_.max_imu_gap_s, &msg);
  if (!msg.empty()) spdlog::warn("{}{}", kLog, msg);
  return res == ImuBuffer::AddResult::kAccepted;
}

SlidingWindowEstimator::Frame* SlidingWindowEstimator::frameById(std::uint64_t id) {
  for (auto& f : frames_)
    if (f->id == id) return f.get();
  return nullptr;
}

void SlidingWindowEstimator::fillState(EstimatorOutput* out) const {
  const Frame& f = *frames_.back();
  out->p_WB = Eigen::Map<const Eigen::Vector3d>(f.pose.data());
  out->q_WB = Eigen::Map<const Eigen::Quaterniond>(f.pose.data() + 3);
  out->v_WB = Eigen::Map<const Eigen::Vector3d>(f.sb.data());
  out->bias.gyro = Eigen::Map<const Eigen::Vector3d>(f.sb.data() + 3);
  out->bias.accel = Eigen::Map<const Eigen::Vector3d>(f.sb.data() + 6);
  out->is_keyframe = f.keyframe;
  out->zero_velocity = f.zero_velocity;
  out->num_frames = static_cast<int>(frames_.size());
  out->num_keyframes = 0;
  for (const auto& fr : frames_) out->num_keyframes += fr->keyframe ? 1 : 0;
}

EstimatorOutput SlidingWindowEstimator::addFrame(const FeatureFrame& input) {
  const auto t_start = Clock::now();
  const double cpu_start = threadCpuMs();
  EstimatorOutput out;
  out.t = input.t;
  out.frame_index = input.frame_index;
  std::ostringstream msg;

  auto reject = [&](const std::string& why) {
    EstimatorOutput r = last_output_;
    r.t = input.t;
    r.frame_index = input.frame_index;
    r.frame_accepted = false;
    r.status = status();
    r.message = why;
    r.timings = EstimatorTimings{};
    r.timings.total_ms = msSince(t_start);
    r.timings.cpu_total_ms = threadCpuMs() - cpu_start;
    return r;
  };

  if (have_last_frame_t_ && input.t <= last_frame_t_) {
    std::ostringstream os;
    os << "frame " << input.frame_index << " at t=" << input.t << " ns is " << (input.t == last_frame_t_ ? "a duplicate" : "older than")
       << " the last frame (t=" << last_frame_t_ << " ns); skipped";
    spdlog::warn("{}{}", kLog, os.str());
    return reject(os.str());
  }

  // Parse features; bad observations are skipped, never trusted.
  auto parse = [&]() {
    auto f = makeFrame();
    f->t = input.t;
    f->frame_index = input.frame_index;
    int invalid = 0, duplicate = 0;
    for (const auto& o : input.features) {
      if (!o.normalized.allFinite() || o.camera_index > 1) {
        ++invalid;
        continue;
      }
      auto& map = o.camera_index == 0 ? f->cam0 : f->cam1;
      if (!map.emplace(o.track_id, o.normalized).second) ++duplicate;
    }
    std::ostringstream m;
    if (invalid > 0) m << "skipped " << invalid << " feature observations with non-finite coordinates or bad camera index; ";
    if (duplicate > 0) m << "skipped " << duplicate << " duplicated track ids; ";
    if (f->cam0.empty()) m << "frame has no features, IMU-only propagation; ";
    return std::make_pair(std::move(f), m.str());
  };
  auto [frame, parse_msg] = parse();
  msg << parse_msg;

  if (!initialized_) {
    std::string init_msg;
    if (!initialize(std::move(frame), &init_msg)) {
      if (!init_msg.empty()) spdlog::debug("{}{}", kLog, init_msg);
      return reject(msg.str() + init_msg);
    }
    msg << init_msg;
    have_last_frame_t_ = true;
    last_frame_t_ = input.t;
    solve(&out);
    if (options_.compute_covariance) computeCovariance(&out);
    fillState(&out);
    out.conflict = monitor_->process(input.t, newest().cam0, newest().cam1, {}, imu_).report;
    commitToMonitor(&out);
    out.status = EstimatorStatus::kTracking;
    out.frame_accepted = true;
    out.message = msg.str();
    out.timings.total_ms = msSince(t_start);
    out.timings.cpu_total_ms = threadCpuMs() - cpu_start;
    last_good_p_ = out.p_WB;
    last_good_yaw_ = yawOf(out.q_WB);
    last_output_ = out;
    return out;
  }

  // Preintegrate from the newest frame.
  auto t_stage = Clock::now();
  Frame& prev = newest();
  std::vector<ImuSample> samples;
  double gap = 0;
  std::string reset_reason;
  if (!imu_.extract(prev.t, input.t, &samples, &gap)) {
    if (imu_.empty() || imu_.lastTime() < input.t) {
      std::ostringstream os;
      os << "no IMU up to frame " << input.frame_index << " at t=" << input.t << " ns (IMU ends at "
         << (imu_.empty() ? 0 : imu_.lastTime()) << " ns); frame skipped";
      spdlog::warn("{}{}", kLog, os.str());
      return reject(msg.str() + os.str());
    }
    reset_reason = "IMU history does not reach back to the previous frame";
  } else if (gap > options_.max_imu_gap_s) {
    std::ostringstream os;
    os << "IMU gap of " << gap << " s between frames (max_imu_gap_s " << options_.max_imu_gap_s << ")";
    reset_reason = os.str();
  }
  have_last_frame_t_ = true;
  last_frame_t_ = input.t;

  auto reinitialize = [&](const std::string& reason) {
    reset(reason);
    auto [fresh, ignored] = parse();
    std::string init_msg;
    EstimatorOutput r;
    r.t = input.t;
    r.frame_index = input.frame_index;
    if (initialize(std::move(fresh), &init_msg)) {
      solve(&r);
      if (options_.compute_covariance) computeCovariance(&r);
      fillState(&r);
      r.conflict = monitor_->process(input.t, newest().cam0, newest().cam1, {}, imu_).report;
      commitToMonitor(&r);
      r.frame_accepted = true;
      last_good_p_ = r.p_WB;
      last_good_yaw_ = yawOf(r.q_WB);
    }
    r.status = EstimatorStatus::kReset;
    r.message = msg.str() + "reset: " + reason + "; " + init_msg;
    r.timings.total_ms = msSince(t_start);
    r.timings.cpu_total_ms = threadCpuMs() - cpu_start;
    last_output_ = r;
    return r;
  };
  if (!reset_reason.empty()) return reinitialize(reset_reason);

  const ImuBias prev_bias{Eigen::Map<const Eigen::Vector3d>(prev.sb.data() + 3),
                          Eigen::Map<const Eigen::Vector3d>(prev.sb.data() + 6)};
  auto pre = std::make_unique<ImuPreintegrator>(prev_bias, imu_noise_);
  for (const auto& s : samples) pre->integrate(s);
  Eigen::Vector3d p_pred, v_pred;  // p_pred: the failure check's reference
  Eigen::Quaterniond q_pred;
  pre->predict(Eigen::Map<const Eigen::Vector3d>(prev.pose.data()), Eigen::Map<const Eigen::Quaterniond>(prev.pose.data() + 3),
               Eigen::Map<const Eigen::Vector3d>(prev.sb.data()), prev_bias, gravity_, &p_pred, &q_pred, &v_pred);
  frame->id = next_frame_id_++;
  Eigen::Map<Eigen::Vector3d>(frame->pose.data()) = p_pred;
  Eigen::Map<Eigen::Quaterniond>(frame->pose.data() + 3) = q_pred;
  Eigen::Map<Eigen::Vector3d>(frame->sb.data()) = v_pred;
  for (int i = 3; i < 9; ++i) frame->sb[static_cast<std::size_t>(i)] = prev.sb[static_cast<std::size_t>(i)];
  frame->imu = std::move(pre);
  frames_.push_back(std::move(frame));
  out.timings.preintegration_ms = msSince(t_stage);

  t_stage = Clock::now();
  Frame& cur = newest();
  MotionConflictMonitor::FrontendVerdicts frontend;
  for (const auto& o : input.features) {
    if (o.camera_index != 0 || o.label == TrackLabel::kUnknown) continue;
    ++frontend.checked;
    (o.label == TrackLabel::kInconsistent ? frontend.inconsistent : frontend.consistent).insert(o.track_id);
  }
  const auto decision = monitor_->process(input.t, cur.cam0, cur.cam1, frontend, imu_);
  out.conflict = decision.report;
  applyConflictDecision(decision, cur);
  if (decision.rewind) p_pred = decision.rewind_state.p;
  if (decision.restart_on_exit) p_pred = decision.exit_state.p;
  out.timings.conflict_ms = msSince(t_stage);
  createLandmarks(cur, &out.num_new_landmarks);
  cur.keyframe = decideKeyframe(cur);
  cur.zero_velocity = options_.zero_velocity_enabled && !decision.suppress_zero_velocity && frames_.size() >= 2 &&
                      detectZeroVelocity(*frames_[frames_.size() - 2], cur);
  repropagateImu();
  out.timings.setup_ms = msSince(t_stage);

  solve(&out);
  removeOutliers(&out);
  for (const auto& [id, o] : cur.cam0) out.num_tracked_features += landmarks_.count(id) != 0 ? 1 : 0;
  if (out.num_visual_residuals >= 10) last_vision_t_ = input.t;

  const std::string failure = checkFailure(p_pred);
  if (!failure.empty()) return reinitialize(failure);

  t_stage = Clock::now();
  if (options_.compute_covariance) computeCovariance(&out);
  out.timings.covariance_ms = msSince(t_stage);
  fillState(&out);
  commitToMonitor(&out);
  if (monitor_->smoothingReady()) smoothConflictWindow(&out);
  t_stage = Clock::now();
  marginalize();
  out.timings.marginalization_ms = msSince(t_stage);
  imu_.dropBefore(std::min(input.t - fromSeconds(options_.init_window_s + 0.1),
                           monitor_->oldestTimeNeeded() - fromSeconds(0.1)));

  out.status = EstimatorStatus::kTracking;
  out.frame_accepted = true;
  out.message = msg.str();
  // One line per frame for `mcvio --log-level debug`: what the solve had and where the biases went.
  if (spdlog::default_logger_raw()->should_log(spdlog::level::debug)) {
    const Eigen::Vector3d& ba = out.bias.accel;
    const Eigen::Vector3d& bg = out.bias.gyro;
    spdlog::debug(
        "{}frame {} t={}: {}keyframe, {} landmarks, {} visual residuals, {} new, {} outliers, {} iterations, "
        "ba ({:.4f} {:.4f} {:.4f}), bg ({:.5f} {:.5f} {:.5f}), conflict {} ({}){}{}",
        kLog, input.frame_index, input.t, out.is_keyframe ? "" : "no ", out.num_landmarks, out.num_visual_residuals,
        out.num_new_landmarks, out.num_outliers, out.solver_iterations, ba.x(), ba.y(), ba.z(), bg.x(), bg.y(), bg.z(),
        toString(out.conflict.state), out.conflict.resolution_mode, out.message.empty() ? "" : "; ", out.message);
  }
  out.timings.total_ms = msSince(t_start);
  out.timings.cpu_total_ms = threadCpuMs() - cpu_start;
  last_good_p_ = out.p_WB;
  last_good_yaw_ = yawOf(out.q_WB);
  last_output_ = out;
  return out;
}

bool SlidingWindowEstimator::initialize(FramePtr frame, std::string* message) {
  const Timestamp t = frame->t;
  const Timestamp window = fromSeconds(options_.init_window_s);
  if (imu_.empty() || imu_.lastTime() < t) {
    *message = "waiting for IMU up to the frame time before initialising";
    return false;
  }
  if (imu_.firstTime() > t - window) {
    std::ostringstream os;
    os << "waiting for " << options_.init_window_s << " s of IMU history before initialising";
    *message = os.str();
    return false;
  }
  const auto samples = imu_.between(t - window, t);
  if (samples.size() < 10) {
    *message = "too few IMU samples in the initialisation window";
    return false;
  }
  std::vector<Eigen::Vector3d> gyro, accel;
  Eigen::Vector3d mean_g = Eigen::Vector3d::Zero(), mean_a = Eigen::Vector3d::Zero();
  for (const auto& s : samples) {
    gyro.push_back(s.gyro);
    accel.push_back(s.accel);
    mean_g += s.gyro;
    mean_a += s.accel;
  }
  mean_g /= static_cast<double>(samples.size());
  mean_a /= static_cast<double>(samples.size());
  const double std_g = stdDev(gyro).norm(), std_a = stdDev(accel).norm();
  const bool still = std_g < options_.static_gyro_std_max && std_a < options_.static_accel_std_max;

  // At rest the accelerometer measures R_WB^T (0, 0, g): that fixes roll and pitch; yaw is free
  // (gauge) and continues from the last good estimate.
  Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(mean_a, Eigen::Vector3d::UnitZ());
  q = Eigen::AngleAxisd(last_good_yaw_ - yawOf(q), Eigen::Vector3d::UnitZ()) * q;
  q.normalize();
  frame->id = next_frame_id_++;
  Eigen::Map<Eigen::Vector3d>(frame->pose.data()) = last_good_p_;
  Eigen::Map<Eigen::Quaterniond>(frame->pose.data() + 3) = q;
  frame->sb.fill(0.0);
  if (still) Eigen::Map<Eigen::Vector3d>(frame->sb.data() + 3) = mean_g;
  frame->keyframe = true;
  frame->has_speed_bias = true;

  const double s_rp = still ? options_.init_roll_pitch_sigma : options_.init_roll_pitch_sigma_moving;
  const double s_v = still ? options_.init_velocity_sigma_static : options_.init_velocity_sigma_moving;
  const double s_bg = still ? options_.init_gyro_bias_sigma_static : options_.init_gyro_bias_sigma_moving;
  whole_prior_.reset();
  prior_ = std::make_shared<MarginalizationPrior>();
  prior_->blocks.push_back({frame->pose.data(), BlockKind::kPose, 7, 6, {frame->pose.begin(), frame->pose.end()}});
  prior_->blocks.push_back({frame->sb.data(), BlockKind::kEuclidean, 9, 9, {frame->sb.begin(), frame->sb.end()}});
  prior_->J = Eigen::MatrixXd::Zero(15, 15);
  prior_->J.block<3, 3>(0, 0) = Eigen::Matrix3d::Identity() / options_.init_position_sigma;
  // Body-frame rotation error mapped to world roll/pitch/yaw: dtheta_W = R_WB dtheta_B.
  prior_->J.block<3, 3>(3, 3) =
      Eigen::Vector3d(1.0 / s_rp, 1.0 / s_rp, 1.0 / options_.init_yaw_sigma).asDiagonal() * q.toRotationMatrix();
  prior_->J.block<3, 3>(6, 6) = Eigen::Matrix3d::Identity() / s_v;
  prior_->J.block<3, 3>(9, 9) = Eigen::Matrix3d::Identity() / s_bg;
  prior_->J.block<3, 3>(12, 12) = Eigen::Matrix3d::Identity() / options_.init_accel_bias_sigma;
  prior_->r = Eigen::VectorXd::Zero(15);

  frames_.clear();
  clearLandmarks();
  frames_.push_back(std::move(frame));
  int created = 0;
  createLandmarks(newest(), &created);
  initialized_ = true;
  last_vision_t_ = t;
  settled_t_ = t + fromSeconds(options_.model_agreement_settle_s);
  std::ostringstream os;
  const Eigen::Vector3d g_body = q.conjugate() * Eigen::Vector3d::UnitZ();
  os << "initialised (" << (still ? "static" : "moving") << " start, gyro std " << std_g << " rad/s, accel std " << std_a
     << " m/s^2, gravity in body " << g_body.transpose() << ", " << created << " stereo landmarks); ";
  *message = os.str();
  spdlog::info("{}{}", kLog, os.str());
  return true;
}

bool SlidingWindowEstimator::triangulateStereo(const Eigen::Vector2d& n0, const Eigen::Vector2d& n1,
                                               double* depth) const {
  // d0 * b0 = R_C0C1 * (d1 * b1) + t_C0C1, least squares in (d0, d1).
  const Eigen::Isometry3d T_C0C1 = T_C1C0_.inverse();
  const Eigen::Vector3d b0(n0.x(), n0.y(), 1.0), b1(n1.x(), n1.y(), 1.0);
  Eigen::Matrix<double, 3, 2> A;
  A.col(0) = b0;
  A.col(1) = -(T_C0C1.linear() * b1);
  const Eigen::Vector2d d = A.colPivHouseholderQr().solve(T_C0C1.translation());
  if (!(d[0] > options_.min_depth_m && d[0] < options_.max_depth_m && d[1] > 0)) return false;
  const Eigen::Vector3d p_C1 = T_C1C0_ * (b0 * d[0]);
  const double err_px = (p_C1.head<2>() / p_C1.z() - n1).norm() * focal_px_;
  if (err_px > options_.outlier_threshold_px) return false;
  const Eigen::Vector3d p_C1_far = T_C1C0_.linear() * b0;  // point at infinity
  const double disparity_px = (p_C1_far.head<2>() / p_C1_far.z() - n1).norm() * focal_px_;
  if (disparity_px < options_.min_stereo_disparity_px) return false;
  *depth = d[0];
  return true;
}

void SlidingWindowEstimator::createLandmarks(Frame& frame, int* created) {
  for (const auto& [track, n0] : frame.cam0) {
    if (landmarks_.count(track) != 0 || monitor_->isEliminated(track)) continue;
    const auto it = frame.cam1.find(track);
    if (it == frame.cam1.end()) continue;
    double depth = 0;
    if (!triangulateStereo(n0, it->second, &depth)) continue;
    Landmark lm;
    lm.track_id = track;
    lm.anchor_frame = frame.id;
    lm.created = frame.t;
    placeLandmark(lm);
    lm.param[0] = n0.x();
    lm.param[1] = n0.y();
    lm.param[2] = 1.0 / depth;
    landmarks_.emplace(track, lm);
    ++*created;
  }
}

bool SlidingWindowEstimator::decideKeyframe(const Frame& frame) const {
  const Frame* kf = nullptr;
  for (auto it = frames_.rbegin(); it != frames_.rend(); ++it)
    if ((*it)->keyframe && it->get() != &frame) {
      kf = it->get();
      break;
    }
  if (kf == nullptr) return true;
  int in_kf = 0, common = 0;
  double parallax = 0;
  for (const auto& [track, n] : kf->cam0) {
    if (landmarks_.count(track) == 0) continue;
    ++in_kf;
    const auto it = frame.cam0.find(track);
    if (it == frame.cam0.end()) continue;
    ++common;
    parallax += (it->second - n).norm() * focal_px_;
  }
  if (in_kf == 0 || common == 0) return true;
  if (static_cast<double>(common) / in_kf < options_.keyframe_tracked_fraction) return true;
  return parallax / common > options_.keyframe_parallax_px;
}

bool SlidingWindowEstimator::detectZeroVelocity(const Frame& prev, const Frame& cur) const {
  const auto samples = imu_.between(prev.t, cur.t);
  if (samples.size() < 3) return false;
  std::vector<Eigen::Vector3d> g, a;
  for (const auto& s : samples) {
    g.push_back(s.gyro);
    a.push_back(s.accel);
  }
  if (stdDev(g).norm() > options_.zero_velocity_gyro_std_max || stdDev(a).norm() > options_.zero_velocity_accel_std_max)
    return false;
  int common = 0;
  double disparity = 0;
  for (const auto& [track, n] : cur.cam0) {
    const auto it = prev.cam0.find(track);
    if (it == prev.cam0.end()) continue;
    ++common;
    disparity += (n - it->second).norm() * focal_px_;
  }
  return common >= 5 && disparity / common < options_.zero_velocity_max_disparity_px;
}

void SlidingWindowEstimator::repropagateImu() {
  for (std::size_t i = 1; i < frames_.size(); ++i) {
    Frame& f = *frames_[i];
    if (!f.imu) continue;
    const Frame& p = *frames_[i - 1];
    const ImuBias b{Eigen::Map<const Eigen::Vector3d>(p.sb.data() + 3), Eigen::Map<const Eigen::Vector3d>(p.sb.data() + 6)};
    if (f.imu->needsRepropagation(b, options_.repropagate_gyro_bias_change, options_.repropagate_accel_bias_change)) {
      f.imu->repropagate(b);
      f.imu_cost.reset();
    }
  }
}

bool SlidingWindowEstimator::landmarkPointWorld(const Landmark& lm, Eigen::Vector3d* p_W) const {
  const Frame* a = nullptr;
  for (const auto& f : frames_)
    if (f->id == lm.anchor_frame) a = f.get();
  if (a == nullptr || !(lm.param[2] > 0)) return false;
  const Eigen::Vector3d p_B = T_BC0_ * (Eigen::Vector3d(lm.param[0], lm.param[1], 1.0) / lm.param[2]);
  *p_W = Eigen::Map<const Eigen::Quaterniond>(a->pose.data() + 3) * p_B + Eigen::Map<const Eigen::Vector3d>(a->pose.data());
  return true;
}

std::vector<Eigen::Vector3d> SlidingWindowEstimator::landmarkPositions() const {
  std::vector<Eigen::Vector3d> out;
  for (const auto& [id, lm] : landmarks_) {
    Eigen::Vector3d p;
    if (landmarkPointWorld(lm, &p)) out.push_back(p);
  }
  return out;
}

void SlidingWindowEstimator::solve(EstimatorOutput* out) {
  const auto t0 = Clock::now();
  records_.clear();
  problem_.reset();
  extra_costs_.clear();
  for (auto it = observation_costs_.begin(); it != observation_costs_.end();)
    it = landmarks_.count(it->first) == 0 ? observation_costs_.erase(it) : std::next(it);
  problem_ = std::make_unique<ProblemHolder>();
  ceres::Problem::Options popts;
  popts.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popts.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popts.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popts.enable_fast_removal = false;
  // The checks (a sorted copy of every residual's blocks, aliasing look-ups) cost an allocation per
  // residual and frame; every residual here has distinct, registered blocks of the declared sizes.
  popts.disable_all_safety_checks = true;
  problem_->problem = std::make_unique<ceres::Problem>(popts);
  ceres::Problem& problem = *problem_->problem;
  auto add = [&](ceres::CostFunction* cost, std::initializer_list<double*> params, ResidualKind kind) {
    records_.emplace_back(cost, nullptr, params, kind);
    problem.AddResidualBlock(cost, nullptr, records_.back().params(), records_.back().num_params);
  };
  auto own = [&](ceres::CostFunction* cost) { return extra_costs_.emplace_back(cost).get(); };
  records_.reserve(4096);

  for (auto& f : frames_) {
    problem.AddParameterBlock(f->pose.data(), 7, &pose_manifold_);
    if (f->has_speed_bias) {
      problem.AddParameterBlock(f->sb.data(), 9);
      if (f->bias_held) problem.SetManifold(f->sb.data(), bias_hold_manifold_.get());
    }
  }
  if (prior_) {
    auto* cost = new MarginalizationFactor(prior_);
    own(cost);
    records_.emplace_back(cost, cost->parameterBlocks());
    problem.AddResidualBlock(cost, nullptr, records_.back().params(), records_.back().num_params);
  }
  for (std::size_t i = 1; i < frames_.size(); ++i) {
    Frame& f = *frames_[i];
    Frame& p = *frames_[i - 1];
    if (!f.imu || !f.has_speed_bias || !p.has_speed_bias) continue;
    // Making the factor inverts and factorises the preintegration's covariance: once per preintegration.
    if (!f.imu_cost) f.imu_cost.reset(ImuFactor::create(*f.imu, gravity_));
    add(f.imu_cost.get(), {p.pose.data(), p.sb.data(), f.pose.data(), f.sb.data()}, ResidualKind::kImu);
  }
  for (auto& f : frames_) {
    if (!f->has_vision_rotation) continue;
    Frame* prev = frameById(f->rotation_prev_id);
    if (prev == nullptr) continue;  // already folded into the prior with the previous frame
    add(own(RelativeRotationFactor::create(f->vision_rotation, f->vision_rotation_sqrt_info)),
        {prev->pose.data(), f->pose.data()}, ResidualKind::kVisionRotation);
  }
  for (auto& f : frames_)
    if (f->zero_velocity && f->has_speed_bias)
      add(own(new ZeroVelocityFactor(options_.zero_velocity_sigma)), {f->sb.data()}, ResidualKind::kZeroVelocity);

  ceres::ParameterBlockOrdering* ordering = new ceres::ParameterBlockOrdering;
  int n_landmarks = 0, n_visual = 0;
  std::vector<ResidualRecord> pending;
  for (auto& [track, lm] : landmarks_) {
    Frame* anchor = frameById(lm.anchor_frame);
    if (anchor == nullptr || !(lm.param[2] > 0) || monitor_->onProbation(track, lm.created)) continue;
    auto& costs = observation_costs_[track];
    auto cachedCost = [&](std::uint64_t frame_id, int camera, bool in_anchor,
                          const Eigen::Vector2d& measured) -> ObservationCost& {
      for (auto& c : costs)
        if (c.frame_id == frame_id && c.camera == camera && c.in_anchor == in_anchor) return c;
      ObservationCost c;
      c.frame_id = frame_id;
      c.camera = camera;
      c.in_anchor = in_anchor;
      const Eigen::Isometry3d& T_CC0 = camera == 0 ? Eigen::Isometry3d::Identity() : T_C1C0_;
      const Eigen::Isometry3d& T_BC = camera == 0 ? T_BC0_ : T_BC1_;
      if (const auto J = localPixelJacobian(camera, measured)) {
        const Eigen::Matrix2d sqrt_information = *J / options_.observation_sigma_px;
        if (in_anchor) c.cost = std::make_unique<AnchorObservationFactor>(measured, T_CC0, sqrt_information);
        else c.cost = std::make_unique<ReprojectionFactor>(measured, T_BC0_, T_BC, sqrt_information);
      } else {
        const double scale = focal_px_ / options_.observation_sigma_px;
        if (in_anchor) c.cost = std::make_unique<AnchorObservationFactor>(measured, T_CC0, scale);
        else c.cost = std::make_unique<ReprojectionFactor>(measured, T_BC0_, T_BC, scale);
      }
      costs.push_back(std::move(c));
      return costs.back();
    };
    pending.clear();
    for (auto& f : frames_) {
      for (int c = 0; c < 2; ++c) {
        // Right-camera observations outside the anchor frame only when configured.
        if (c == 1 && f.get() != anchor && !options_.right_camera_in_all_frames) continue;
        const auto& map = c == 0 ? f->cam0 : f->cam1;
        const auto it = map.find(track);
        if (it == map.end()) continue;
        if (f.get() == anchor) {
          ceres::CostFunction* cost = cachedCost(f->id, c, true, it->second).cost.get();
          pending.emplace_back(cost, loss_.get(), std::initializer_list<double*>{lm.param}, ResidualKind::kVisual);
          pending.back().track_id = track;
          pending.back().frame_id = f->id;
          pending.back().camera = c;
          continue;
        }
        auto* cost = static_cast<ReprojectionFactor*>(cachedCost(f->id, c, false, it->second).cost.get());
        Eigen::Vector3d p_C;
        if (!cost->pointInCamera(anchor->pose.data(), f->pose.data(), lm.param, &p_C)) continue;
        pending.emplace_back(cost, loss_.get(),
                             std::initializer_list<double*>{anchor->pose.data(), f->pose.data(), lm.param},
                             ResidualKind::kVisual);
        pending.back().track_id = track;
        pending.back().frame_id = f->id;
        pending.back().camera = c;
      }
    }
    // A landmark seen only in its anchor frame constrains no pose yet.
    bool constrains_pose = false;
    for (const auto& r : pending) constrains_pose |= r.num_params > 1;
    if (constrains_pose) {
      problem.AddParameterBlock(lm.param, 3);
      ordering->AddElementToGroup(lm.param, 0);
      ++n_landmarks;
      for (auto& r : pending) {
        problem.AddResidualBlock(r.cost, r.loss, r.params(), r.num_params);
        records_.push_back(std::move(r));
        ++n_visual;
      }
    }
    // Cost functions of observations that are not in this problem go.
    for (auto& c : costs)
      c.used = constrains_pose &&
               std::any_of(pending.begin(), pending.end(), [&](const ResidualRecord& r) { return r.cost == c.cost.get(); });
    costs.erase(std::remove_if(costs.begin(), costs.end(), [](const ObservationCost& c) { return !c.used; }),
                costs.end());
  }
  for (auto& f : frames_) {
    ordering->AddElementToGroup(f->pose.data(), 1);
    if (f->has_speed_bias) ordering->AddElementToGroup(f->sb.data(), 1);
  }
  out->num_landmarks = n_landmarks;
  out->num_visual_residuals = n_visual;
  out->timings.setup_ms += msSince(t0);

  const auto t1 = Clock::now();
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.linear_solver_ordering.reset(ordering);
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.max_num_iterations = options_.max_iterations;
  const bool resolving = resolvingConflict();
  so.function_tolerance = resolving ? options_.conflict_function_tolerance : options_.function_tolerance;
  // Not while a conflict is being resolved: eliminated landmarks and held biases move the minimum
  // further than one step goes, however well that step met its model.
  ModelAgreementStop stop(so.function_tolerance);
  if (options_.stop_on_model_agreement && !resolving && newest().t >= settled_t_) so.callbacks.push_back(&stop);
  so.max_solver_time_in_seconds = options_.max_solver_time_s;
  so.num_threads = options_.num_threads;
  so.logging_type = ceres::SILENT;
  // Steps here stay far inside the trust region, so LM's column scaling does not change them (the
  // benchmark's trajectories came out identical); it cost two passes over the Jacobian per iteration.
  so.jacobi_scaling = false;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  out->solver_iterations = static_cast<int>(summary.iterations.size()) - 1;
  out->timings.solve_ms = msSince(t1);
  if (summary.termination_type == ceres::FAILURE || summary.termination_type == ceres::NO_CONVERGENCE)
    spdlog::debug("{}solve at t={}: {} ({})", kLog, newest().t, ceres::TerminationTypeToString(summary.termination_type),
                  summary.message);
}

void SlidingWindowEstimator::removeOutliers(EstimatorOutput* out) {
  const double sigma = options_.observation_sigma_px;
  std::unordered_set<std::uint64_t> to_erase;
  for (auto& r : records_) {
    if (r.kind != ResidualKind::kVisual || !r.valid) continue;
    Eigen::Vector2d res;
    const bool ok = r.cost->Evaluate(r.params(), res.data(), nullptr);
    if (ok && res.norm() * sigma <= options_.outlier_threshold_px) continue;
    r.valid = false;
    ++out->num_outliers;
    Frame* f = frameById(r.frame_id);
    if (f != nullptr) (r.camera == 0 ? f->cam0 : f->cam1).erase(r.track_id);
    if (options_.outlier_drops_landmark) to_erase.insert(r.track_id);
  }
  for (const auto& [track, lm] : landmarks_) {
    const double depth = lm.depth();
    if (!(depth >= options_.min_depth_m && depth <= options_.max_depth_m)) to_erase.insert(track);
  }
  for (std::uint64_t t : to_erase) eraseLandmark(t);
}

void SlidingWindowEstimator::eraseLandmark(std::uint64_t track_id) {
  for (auto& f : frames_) {
    f->cam0.erase(track_id);
    f->cam1.erase(track_id);
  }
  const auto it = landmarks_.find(track_id);
  if (it != landmarks_.end()) {
    landmark_params_.release(it->second.slot);
    landmarks_.erase(it);
  }
  for (auto& r : records_)
    if (r.kind == ResidualKind::kVisual && r.track_id == track_id) r.valid = false;
}

std::string SlidingWindowEstimator::checkFailure(const Eigen::Vector3d& p_pred) const {
  const Frame& f = *frames_.back();
  std::ostringstream os;
  for (const auto& fr : frames_) {
    for (double x : fr->pose)
      if (!std::isfinite(x)) return "non-finite pose in the window";
    for (double x : fr->sb)
      if (!std::isfinite(x)) return "non-finite velocity or bias in the window";
  }
  const Eigen::Vector3d p = Eigen::Map<const Eigen::Vector3d>(f.pose.data());
  const Eigen::Vector3d v = Eigen::Map<const Eigen::Vector3d>(f.sb.data());
  const Eigen::Vector3d bg = Eigen::Map<const Eigen::Vector3d>(f.sb.data() + 3);
  const Eigen::Vector3d ba = Eigen::Map<const Eigen::Vector3d>(f.sb.data() + 6);
  if (v.norm() > options_.max_speed_mps) os << "speed " << v.norm() << " m/s exceeds max_speed_mps";
  else if (bg.norm() > options_.max_gyro_bias) os << "gyro bias " << bg.norm() << " rad/s exceeds max_gyro_bias";
  else if (ba.norm() > options_.max_accel_bias) os << "accel bias " << ba.norm() << " m/s^2 exceeds max_accel_bias";
  else if ((p - p_pred).norm() > options_.max_position_jump_m)
    os << "position moved " << (p - p_pred).norm() << " m away from the IMU prediction (max_position_jump_m)";
  else if (!monitor_->imuDominated() && toSeconds(f.t - last_vision_t_) > options_.max_time_without_vision_s)
    os << "no visual constraints for " << toSeconds(f.t - last_vision_t_) << " s";
  return os.str();
}

void SlidingWindowEstimator::computeCovariance(EstimatorOutput* out) {
  Marginalizer m;
  for (auto& f : frames_) {
    m.addParameterBlock(f->pose.data(), BlockKind::kPose, 7);
    if (f->has_speed_bias) m.addParameterBlock(f->sb.data(), BlockKind::kEuclidean, 9);
  }
  for (auto& [track, lm] : landmarks_) m.addParameterBlock(lm.param, BlockKind::kLandmark, 3);
  // The whole information stands in for the solver's prior, its strong part.
  for (const auto& r : records_)
    if (r.valid && !(whole_prior_ && r.kind == ResidualKind::kPrior))
      m.addResidualBlock(r.cost, r.loss, r.params(), r.num_params);
  std::unique_ptr<MarginalizationFactor> whole;
  if (whole_prior_) {
    whole = std::make_unique<MarginalizationFactor>(whole_prior_);
    m.addResidualBlock(whole.get(), nullptr, whole->parameterBlocks());
  }
  Frame& f = newest();
  Eigen::MatrixXd cov;
  try {
    if (f.has_speed_bias)
      out->covariance_valid = m.marginalCovariance({f.pose.data(), f.sb.data()}, &cov);
    else
      out->covariance_valid = m.marginalCovariance(f.pose.data(), &cov);
  } catch (const std::exception& e) {
    spdlog::warn("{}covariance failed: {}", kLog, e.what());
    out->covariance_valid = false;
  }
  if (!out->covariance_valid) return;
  out->pose_covariance = cov.topLeftCorner<6, 6>();
  if (!f.has_speed_bias) return;
  // The attitude in the world: the pose's body-frame perturbation turned by R_WB.
  StateCovariance T = StateCovariance::Identity();
  T.block<3, 3>(3, 3) = Eigen::Map<const Eigen::Quaterniond>(f.pose.data() + 3).toRotationMatrix();
  state_covariances_.emplace_back(f.t, T * cov * T.transpose());
  const Timestamp oldest = monitor_->oldestTimeNeeded();
  while (state_covariances_.size() > 1 && state_covariances_[1].first <= oldest) state_covariances_.pop_front();
}

const SlidingWindowEstimator::StateCovariance* SlidingWindowEstimator::stateCovarianceAt(Timestamp t) const {
  const StateCovariance* found = nullptr;
  for (const auto& [ti, c] : state_covariances_)
    if (ti <= t) found = &c;
  return found;
}

void SlidingWindowEstimator::marginalizeWith(const std::vector<const ResidualRecord*>& records,
                                             const std::set<const double*>& drop) {
  Marginalizer m;
  for (auto& f : frames_) {
    m.addParameterBlock(f->pose.data(), BlockKind::kPose, 7);
    if (f->has_speed_bias) m.addParameterBlock(f->sb.data(), BlockKind::kEuclidean, 9);
  }
  for (auto& [track, lm] : landmarks_) m.addParameterBlock(lm.param, BlockKind::kLandmark, 3);
  const ceres::CostFunction* prior_in = nullptr;
  for (const auto* r : records) {
    m.addResidualBlock(r->cost, r->loss, r->params(), r->num_params);
    if (r->kind == ResidualKind::kPrior) prior_in = r->cost;
  }
  try {
    auto split = m.marginalizeSplit(drop, prior_in != nullptr ? whole_prior_.get() : nullptr, prior_in);
    prior_ = std::move(split.prior);
    whole_prior_ = std::move(split.whole);
  } catch (const std::exception& e) {
    // Losing the prior loses information but never adds false information.
    spdlog::warn("{}marginalisation failed ({}); prior dropped", kLog, e.what());
    prior_.reset();
    whole_prior_.reset();
  }
  // The consumed residuals now live in the prior; a second marginalisation in the same frame must
  // see the new prior instead of them.
  for (const auto* r : records) const_cast<ResidualRecord*>(r)->valid = false;
  if (prior_) {
    auto cost = std::make_unique<MarginalizationFactor>(prior_);
    records_.emplace_back(cost.get(), cost->parameterBlocks());
    extra_costs_.push_back(std::move(cost));
  }
}

bool SlidingWindowEstimator::resolvingConflict() const {
  return monitor_->conflictActive() && options_.conflict.mode != conflict::ResolutionMode::kReference;
}

bool SlidingWindowEstimator::historyMayGoOn(std::uint64_t track_id) const {
  if (!resolvingConflict()) return true;
  // A moving landmark's history, once in the prior, could not be eliminated with it.
  return options_.conflict.frontend_conflict_keeps_history && monitor_->conflictFromFrontendOnly() &&
         !monitor_->disagreedRecently(track_id) && !monitor_->isEliminated(track_id);
}

bool SlidingWindowEstimator::newAnchor(const Landmark& lm, std::uint64_t leaving_frame, bool imu_window_only,
                                       std::uint64_t* frame_id, Eigen::Vector3d* param) const {
  Eigen::Vector3d p_W;
  if (!landmarkPointWorld(lm, &p_W)) return false;
  for (const auto& f : frames_) {
    if (f->id == leaving_frame || (imu_window_only && !f->has_speed_bias)) continue;
    const auto it = f->cam0.find(lm.track_id);
    if (it == f->cam0.end()) continue;
    const Eigen::Vector3d p_B =
        Eigen::Map<const Eigen::Quaterniond>(f->pose.data() + 3).conjugate() * (p_W - Eigen::Map<const Eigen::Vector3d>(f->pose.data()));
    const Eigen::Vector3d p_C = T_BC0_.inverse() * p_B;
    if (!(p_C.z() >= options_.min_depth_m && p_C.z() <= options_.max_depth_m)) return false;
    *frame_id = f->id;
    *param = Eigen::Vector3d(p_C.x() / p_C.z(), p_C.y() / p_C.z(), 1.0 / p_C.z());
    return true;
  }
  return false;
}

bool SlidingWindowEstimator::reanchor(Landmark& lm, std::uint64_t leaving_frame, bool imu_window_only) {
  std::uint64_t frame_id = 0;
  Eigen::Vector3d param;
  if (!newAnchor(lm, leaving_frame, imu_window_only, &frame_id, &param)) return false;
  // The estimate moves to the new anchor unchanged; the new anchor's observations stay residuals.
  lm.anchor_frame = frame_id;
  Eigen::Map<Eigen::Vector3d>(lm.param) = param;
  return true;
}

void SlidingWindowEstimator::marginalize() {
  int n_imu = 0;
  for (const auto& f : frames_) n_imu += f->has_speed_bias ? 1 : 0;
  if (n_imu > options_.imu_window_size) marginalizeOldestImuFrame();
  int n_kf = 0;
  for (const auto& f : frames_) n_kf += f->has_speed_bias ? 0 : 1;
  if (n_kf > options_.keyframe_window_size) marginalizeOldestKeyframe();
}

void SlidingWindowEstimator::marginalizeOldestImuFrame() {
  std::size_t io = 0;
  while (io < frames_.size() && !frames_[io]->has_speed_bias) ++io;
  if (io + 1 >= frames_.size()) return;
  Frame& fo = *frames_[io];
  Frame& next = *frames_[io + 1];
  std::set<const double*> drop{fo.sb.data()};
  if (!fo.keyframe) drop.insert(fo.pose.data());
  // Non-visual factors of the leaving states; a non-keyframe's visual observations are dropped
  // (information lost, never invented), which keeps landmarks out of the prior.
  std::vector<const ResidualRecord*> records;
  for (const auto& r : records_) {
    if (!r.valid || r.kind == ResidualKind::kVisual) continue;
    bool touches = r.kind == ResidualKind::kPrior;  // always carried over
    for (int i = 0; i < r.num_params; ++i) touches |= drop.count(r.params()[i]) != 0;
    if (touches) records.push_back(&r);
  }
  marginalizeWith(records, drop);
  next.imu.reset();
  next.imu_cost.reset();
  if (fo.keyframe) {
    fo.has_speed_bias = false;
    return;
  }
  std::vector<std::uint64_t> lost;
  for (auto& [track, lm] : landmarks_)
    if (lm.anchor_frame == fo.id && !reanchor(lm, fo.id)) lost.push_back(track);
  for (auto t : lost) eraseLandmark(t);
  for (auto& r : records_)
    if (r.frame_id == fo.id || (r.num_params > 1 && (r.params()[0] == fo.pose.data() || r.params()[1] == fo.pose.data())))
      r.valid = false;
  frames_.erase(frames_.begin() + static_cast<std::ptrdiff_t>(io));
}

void SlidingWindowEstimator::marginalizeOldestKeyframe() {
  Frame& k0 = *frames_.front();
  if (k0.has_speed_bias) return;
  std::unordered_set<std::uint64_t> alive;
  for (const auto& f : frames_) {
    if (!f->has_speed_bias) continue;
    for (const auto& [t, n] : f->cam0) alive.insert(t);
    for (const auto& [t, n] : f->cam1) alive.insert(t);
  }
  std::unordered_set<std::uint64_t> dead;
  std::set<const double*> drop{k0.pose.data()};
  // marginalize_tracked_landmark_history: a landmark anchored here and still tracked is split.
  // Its observations in the keyframe window leave with this keyframe; it goes on in the IMU window.
  std::unordered_set<std::uint64_t> pose_only_frames, split;
  for (const auto& f : frames_)
    if (!f->has_speed_bias) pose_only_frames.insert(f->id);
  auto consider = [&](std::uint64_t track) {
    const auto it = landmarks_.find(track);
    if (it == landmarks_.end()) return;
    const Landmark& lm = it->second;
    if (alive.count(track) != 0) {
      std::uint64_t frame_id = 0;
      Eigen::Vector3d param;
      if (!options_.marginalize_tracked_landmark_history || lm.anchor_frame != k0.id || !historyMayGoOn(track) ||
          !newAnchor(lm, k0.id, true, &frame_id, &param))
        return;
      split.insert(track);
    }
    if (dead.insert(track).second) drop.insert(lm.param);
  };
  for (const auto& [t, n] : k0.cam0) consider(t);
  for (const auto& [t, n] : k0.cam1) consider(t);
  // Landmarks seen only by keyframes leave with this keyframe, all their observations folded
  // into the prior; landmarks still tracked lose this keyframe's observations only (or, split,
  // their keyframe window's).
  std::vector<const ResidualRecord*> records;
  for (const auto& r : records_) {
    if (!r.valid) continue;
    bool take = r.kind == ResidualKind::kPrior;
    if (r.kind == ResidualKind::kVisual) {
      take = dead.count(r.track_id) != 0 && (split.count(r.track_id) == 0 || pose_only_frames.count(r.frame_id) != 0);
    } else {
      for (int i = 0; i < r.num_params; ++i) take |= r.params()[i] == k0.pose.data();
    }
    if (take) records.push_back(&r);
  }
  marginalizeWith(records, drop);
  for (const auto t : split) {
    reanchor(landmarks_.at(t), k0.id, true);
    for (auto& f : frames_)
      if (!f->has_speed_bias) {
        f->cam0.erase(t);
        f->cam1.erase(t);
      }
  }
  for (auto t : dead) {
    if (split.count(t) != 0) continue;
    rememberLandmark(t, newest().t);
    eraseLandmark(t);
  }
  std::vector<std::uint64_t> lost;
  for (auto& [track, lm] : landmarks_)
    if (lm.anchor_frame == k0.id && !reanchor(lm, k0.id)) lost.push_back(track);
  for (auto t : lost) {
    rememberLandmark(t, newest().t);
    eraseLandmark(t);
  }
  for (auto& r : records_)
    if (r.frame_id == k0.id || (r.num_params > 1 && (r.params()[0] == k0.pose.data() || r.params()[1] == k0.pose.data())))
      r.valid = false;
  frames_.pop_front();
}

void SlidingWindowEstimator::reset(const std::string& reason) {
  spdlog::warn("{}reset at t={} ns: {} (re-initialising at the last good position and yaw)", kLog,
               frames_.empty() ? 0 : frames_.back()->t, reason);
  records_.clear();
  problem_.reset();
  extra_costs_.clear();
  observation_costs_.clear();
  frames_.clear();
  clearLandmarks();
  prior_.reset();
  whole_prior_.reset();
  state_covariances_.clear();
  initialized_ = false;
  monitor_->reset();
  map_memory_.clear();
  ++reset_count_;
}

void SlidingWindowEstimator::commitToMonitor(EstimatorOutput* out) {
  MotionConflictMonitor::State s;
  s.p = out->p_WB;
  s.q = out->q_WB;
  s.v = out->v_WB;
  s.bias = out->bias;
  monitor_->commit(s, &out->conflict);
}

void SlidingWindowEstimator::applyConflictDecision(const MotionConflictMonitor::Decision& decision, Frame& cur) {
  for (const auto id : decision.eliminate) eraseLandmark(id);
  // Prior sigmas of a restarted window: position, world roll/pitch/yaw, velocity, gyro and accel bias.
  const auto& c = options_.conflict;
  const auto restartSigmas = [&c](double position, double roll_pitch) {
    Eigen::Matrix<double, 15, 1> s;
    s << Eigen::Vector3d::Constant(position), roll_pitch, roll_pitch, c.attitude_sigma_rad,
        Eigen::Vector3d::Constant(c.velocity_sigma_mps), Eigen::Vector3d::Constant(c.gyro_bias_sigma),
        Eigen::Vector3d::Constant(c.accel_bias_sigma);
    return s;
  };
  if (decision.rewind) {
    // The map as it stood when the interval opened, in the frame its conflict window starts in.
    if (options_.conflict.smoothing_reidentified_min_landmarks > 0)
      for (const auto& [track, lm] : landmarks_) {
        Eigen::Vector3d p_W;
        if (!monitor_->isEliminated(track) && landmarkPointWorld(lm, &p_W))
          map_memory_.remember(track, p_W, decision.rewind_t);
      }
    // The rewound state is an estimate propagated over dt: its position spreads with the velocity.
    const double dt = toSeconds(cur.t - decision.rewind_t);
    const double sigma_p = 0.01 + c.velocity_sigma_mps * dt;
    const StateCovariance* then = stateCovarianceAt(decision.rewind_t);
    const Eigen::Matrix3d position =
        (then != nullptr ? Eigen::Matrix3d(then->topLeftCorner<3, 3>()) : Eigen::Matrix3d::Zero()) + sigma_p * sigma_p * Eigen::Matrix3d::Identity();
    restartFrom(cur, decision.rewind_state, restartSigmas(sigma_p, c.attitude_sigma_rad), &position);
    spdlog::info("{}motion conflict at t={} ns: IMU-dominated from the state {:.2f} s back, biases held", kLog, cur.t,
                 dt);
  }
  if (decision.restart_on_exit) {
    // Roll and pitch drifted with the gyro over the interval; gravity tells them again, as at a
    // moving start. Position and yaw continue (unobservable), velocity is vision's.
    // The position carried through the interval is known as the IMU-only window knew it.
    const Eigen::Matrix3d position = (last_output_.covariance_valid ? Eigen::Matrix3d(last_output_.pose_covariance.topLeftCorner<3, 3>())
                                                                     : Eigen::Matrix3d::Zero()) +
                                     1e-4 * Eigen::Matrix3d::Identity();
    restartFrom(cur, decision.exit_state, restartSigmas(0.01, options_.init_roll_pitch_sigma_moving), &position);
    const Eigen::Vector3d& v = decision.exit_state.v;
    spdlog::info(
        "{}motion conflict over at t={} ns: window restarted at vision's velocity ({:.2f}, {:.2f}, {:.2f}) m/s, "
        "{:.2f} m/s from the inertial one",
        kLog, cur.t, v.x(), v.y(), v.z(), decision.exit_velocity_jump_mps);
  }
  if (decision.hold_bias) {
    Eigen::Map<Eigen::Vector3d>(cur.sb.data() + 3) = decision.held_bias.gyro;
    Eigen::Map<Eigen::Vector3d>(cur.sb.data() + 6) = decision.held_bias.accel;
    cur.bias_held = true;
  }
  if (!decision.imu_dominated) return;
  // A conflicting camera must neither move the state nor bend the biases.
  clearLandmarks();
  for (auto& f : frames_) {
    f->cam0.clear();
    f->cam1.clear();
  }
  last_vision_t_ = cur.t;
  if (decision.vision_rotation && frames_.size() >= 2) {
    cur.has_vision_rotation = true;
    cur.rotation_prev_id = frames_[frames_.size() - 2]->id;
    cur.vision_rotation = decision.q_prev_cur;
    cur.vision_rotation_sqrt_info = decision.rotation_sqrt_information;
  }
}

void SlidingWindowEstimator::restartFrom(Frame& cur, const MotionConflictMonitor::State& state,
                                         const Eigen::Matrix<double, 15, 1>& sigmas,
                                         const Eigen::Matrix3d* position_covariance) {
  Eigen::Map<Eigen::Vector3d>(cur.pose.data()) = state.p;
  Eigen::Map<Eigen::Quaterniond>(cur.pose.data() + 3) = state.q.normalized();
  Eigen::Map<Eigen::Vector3d>(cur.sb.data()) = state.v;
  Eigen::Map<Eigen::Vector3d>(cur.sb.data() + 3) = state.bias.gyro;
  Eigen::Map<Eigen::Vector3d>(cur.sb.data() + 6) = state.bias.accel;
  cur.imu.reset();
  cur.imu_cost.reset();
  cur.keyframe = true;
  cur.has_speed_bias = true;
  settled_t_ = cur.t + fromSeconds(options_.model_agreement_settle_s);
  FramePtr keep = std::move(frames_.back());
  records_.clear();
  problem_.reset();
  extra_costs_.clear();
  observation_costs_.clear();
  frames_.clear();
  frames_.push_back(std::move(keep));
  clearLandmarks();
  setStatePrior(cur, sigmas);
  if (position_covariance != nullptr) setWindowPositionCovariance(*position_covariance);
}

void SlidingWindowEstimator::setWindowPositionCovariance(const Eigen::Matrix3d& covariance) {
  if (prior_ == nullptr) return;
  if (whole_prior_ == nullptr) {
    // The covariance's information starts as the solver's prior, without its pull (r = 0).
    whole_prior_ = std::make_shared<MarginalizationPrior>(*prior_);
    whole_prior_->r.setZero();
  }
  whole_prior_->setCommonTranslationCovariance(covariance);
}

void SlidingWindowEstimator::rememberLandmark(std::uint64_t track_id, Timestamp t) {
  if (options_.conflict.smoothing_reidentified_min_landmarks <= 0 || monitor_->conflictActive() ||
      monitor_->isEliminated(track_id))
    return;
  const auto it = landmarks_.find(track_id);
  Eigen::Vector3d p_W;
  if (it != landmarks_.end() && landmarkPointWorld(it->second, &p_W)) map_memory_.remember(track_id, p_W, t);
}

bool SlidingWindowEstimator::reidentifiedEnd(const Eigen::Vector3d& p_end,
                                             ConflictIntervalSmoother::ReidentifiedEnd* end) const {
  const int needed = options_.conflict.smoothing_reidentified_min_landmarks;
  if (needed <= 0 || map_memory_.size() == 0) return false;
  const Timestamp opened = monitor_->smoothingStartTime();
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  std::vector<Eigen::Vector3d> current;  // for a registration by position, if the ids do not do
  for (const auto& [track, lm] : landmarks_) {
    Eigen::Vector3d now;
    if (!landmarkPointWorld(lm, &now)) continue;
    if (const Eigen::Vector3d* before = map_memory_.find(track, opened)) pairs.emplace_back(now, *before);
    if (!monitor_->isEliminated(track)) current.push_back(now);
  }
  MapMemory::Offset o = MapMemory::offsetOf(pairs, needed);
  const auto& c = options_.conflict;
  if (!o.valid && c.smoothing_registration_radius_m > 0) {
    // Too few came back with their old ids: find the map by the landmarks' positions.
    LandmarkRegistration::Options ro;
    ro.radius_m = c.smoothing_registration_radius_m;
    ro.tolerance_m = c.smoothing_registration_tolerance_m;
    ro.min_points = needed;
    ro.min_fraction = c.smoothing_registration_min_fraction;
    ro.max_ambiguity = c.smoothing_registration_max_ambiguity;
    const auto t_start = Clock::now();
    // The latest remembered are where the interval began; a long run's whole map would only
    // cost time (every pair within the radius votes).
    constexpr std::size_t kMaxRemembered = 4000;
    const auto remembered = map_memory_.positionsUpTo(opened, kMaxRemembered);
    const auto r = LandmarkRegistration(ro).align(current, remembered);
    spdlog::info("{}map registration: {} of {} landmarks agree on an offset of ({:.3f}, {:.3f}, {:.3f}) m against the "
                 "{} remembered (sharpness {:.1f}, the best distinct offset {:.1f}; {:.1f} ms): {}",
                 kLog, r.support, current.size(), r.offset.x(), r.offset.y(), r.offset.z(), remembered.size(),
                 r.sharpness, r.runner_up_sharpness, msSince(t_start), r.valid ? "used" : "not used");
    if (r.valid) o = MapMemory::offsetOf(r.pairs, needed);
  }
  if (!o.valid) return false;
  // The window drifted by o.offset against the map: the body did too.
  end->p = p_end - o.offset;
  end->sigma = o.sigma;
  end->landmarks = o.inliers;
  return true;
}

void SlidingWindowEstimator::smoothConflictWindow(EstimatorOutput* out) {
  ConflictIntervalSmoother::ReidentifiedEnd end;
  const bool reidentified = reidentifiedEnd(out->p_WB, &end);
  const Timestamp exited = monitor_->smoothingExitTime();
  const StateCovariance* at_start = stateCovarianceAt(monitor_->smoothingStartTime());
  ConflictIntervalSmoother::StartCovariance start;
  if (at_start != nullptr) start = at_start->bottomRightCorner<12, 12>();
  auto res = monitor_->smoothInterval(imu_, reidentified ? &end : nullptr, at_start != nullptr ? &start : nullptr);
  if (!res.applied) {
    spdlog::warn("{}{}", kLog, res.message);
    return;
  }
  // What the map learned since the interval ended (in the drifted window) moves with it.
  map_memory_.shiftAfter(exited, res.shift);
  // A translation of the whole window: landmarks live in their anchor frames, and the prior keeps
  // its information if its linearisation point moves along.
  for (auto& f : frames_) Eigen::Map<Eigen::Vector3d>(f->pose.data()) += res.shift;
  for (auto* prior : {prior_.get(), whole_prior_.get()})
    if (prior != nullptr)
      for (auto& b : prior->blocks)
        if (b.kind == BlockKind::kPose) Eigen::Map<Eigen::Vector3d>(b.x_lin.data()) += res.shift;
  // The correction is not a solve: where the window now is, is known as well as the start and the
  // correction's own error say. The covariance's information takes that (never the solver's prior,
  // so no estimate changes); the window's shape stays as the solves left it.
  if (res.shift_covariance_valid && at_start != nullptr)
    setWindowPositionCovariance(at_start->topLeftCorner<3, 3>() + res.shift_covariance);
  out->p_WB += res.shift;
  out->revised_poses = std::move(res.revisions);
  out->revised_secondary = std::move(res.secondary_revisions);
  spdlog::info("{}{}", kLog, res.message);
}

void SlidingWindowEstimator::setStatePrior(Frame& frame, const Eigen::Matrix<double, 15, 1>& sigmas) {
  whole_prior_.reset();
  prior_ = std::make_shared<MarginalizationPrior>();
  prior_->blocks.push_back({frame.pose.data(), BlockKind::kPose, 7, 6, {frame.pose.begin(), frame.pose.end()}});
  prior_->blocks.push_back({frame.sb.data(), BlockKind::kEuclidean, 9, 9, {frame.sb.begin(), frame.sb.end()}});
  const Eigen::Matrix3d R = Eigen::Map<const Eigen::Quaterniond>(frame.pose.data() + 3).toRotationMatrix();
  prior_->J = Eigen::MatrixXd::Zero(15, 15);
  prior_->J.block<3, 3>(0, 0) = sigmas.segment<3>(0).cwiseInverse().asDiagonal();
  // World-frame attitude error from the body-frame perturbation: dtheta_W = R_WB dtheta_B.
  prior_->J.block<3, 3>(3, 3) = sigmas.segment<3>(3).cwiseInverse().asDiagonal() * R;
  prior_->J.block<3, 3>(6, 6) = sigmas.segment<3>(6).cwiseInverse().asDiagonal();
  prior_->J.block<3, 3>(9, 9) = sigmas.segment<3>(9).cwiseInverse().asDiagonal();
  prior_->J.block<3, 3>(12, 12) = sigmas.segment<3>(12).cwiseInverse().asDiagonal();
  prior_->r = Eigen::VectorXd::Zero(15);
}

}  // namespace mcvio::estimator
