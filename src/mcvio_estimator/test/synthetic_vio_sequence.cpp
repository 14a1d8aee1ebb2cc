#include "synthetic_vio_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <unordered_set>

#include <time.h>

#include "mcvio/estimator/so3.hpp"

namespace mcvio::estimator::testing {

namespace {

// Zero with zero first and second derivative at tau = 0, then rising smoothly to 1.
double envelope(double tau) {
  if (tau <= 0) return 0.0;
  const double x = tau / 2.0;
  return x * x * x * x / (1.0 + x * x * x * x);
}

struct Trajectory {
  double still, scale;
  Eigen::Vector3d position(double t) const {
    const double tau = t - still;
    const double e = envelope(tau) * scale;
    return e * Eigen::Vector3d(2.0 * std::sin(0.45 * tau), 1.5 * (1.0 - std::cos(0.35 * tau)), 0.4 * std::sin(0.6 * tau));
  }
  Eigen::Quaterniond orientation(double t) const {
    const double tau = t - still;
    const double e = envelope(tau);
    const double yaw = e * 0.9 * std::sin(0.3 * tau), pitch = e * 0.15 * std::sin(0.55 * tau),
                 roll = e * 0.1 * std::sin(0.7 * tau);
    return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  }
};

}  // namespace

SyntheticSequence generateSequence(const SyntheticConfig& cfg) {
  SyntheticSequence seq;
  seq.noise = cfg.noise;
  std::mt19937 rng(cfg.seed);
  std::normal_distribution<double> nd;
  std::uniform_real_distribution<double> ud(0.0, 1.0);

  // Camera looks along body x; cam1 is 11 cm to the camera's right.
  Eigen::Matrix3d R_BC;
  R_BC << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  seq.T_BC0 = Eigen::Isometry3d::Identity();
  seq.T_BC0.linear() = R_BC * so3::exp(Eigen::Vector3d(0.01, -0.015, 0.005));
  seq.T_BC0.translation() = Eigen::Vector3d(0.05, 0.03, -0.02);
  seq.T_BC1 = seq.T_BC0;
  seq.T_BC1.linear() = R_BC * so3::exp(Eigen::Vector3d(0.012, -0.01, 0.004));
  seq.T_BC1.translation() = seq.T_BC0.translation() + seq.T_BC0.linear() * Eigen::Vector3d(0.11, 0.0, 0.0);
  const double f = seq.focal_px, cx = 376, cy = 240, width = 752, height = 480;

  // Landmarks on the walls, floor and ceiling of a 14 x 14 x 6 m room.
  std::vector<Eigen::Vector3d> landmarks;
  for (int i = 0; i < cfg.num_landmarks; ++i) {
    const int face = static_cast<int>(ud(rng) * 6);
    const double a = ud(rng), b = ud(rng);
    Eigen::Vector3d p;
    switch (face) {
      case 0: p = {7.0, -7 + 14 * a, -2 + 6 * b}; break;
      case 1: p = {-7.0, -7 + 14 * a, -2 + 6 * b}; break;
      case 2: p = {-7 + 14 * a, 7.0, -2 + 6 * b}; break;
      case 3: p = {-7 + 14 * a, -7.0, -2 + 6 * b}; break;
      case 4: p = {-7 + 14 * a, -7 + 14 * b, -2.0}; break;
      default: p = {-7 + 14 * a, -7 + 14 * b, 4.0}; break;
    }
    landmarks.push_back(p);
  }

  const Trajectory traj{cfg.still_s, cfg.motion_scale};
  const Eigen::Vector3d g(0, 0, -9.81);
  const double dt = 0.005, h = 1e-3;
  const Timestamp t0 = 1'000'000'000;
  const int n_imu = static_cast<int>(cfg.duration_s / dt) + 1;
  Eigen::Vector3d bg = cfg.gyro_bias0, ba = cfg.accel_bias0;
  std::unordered_set<std::size_t> tracked;
  for (int k = 0; k < n_imu; ++k) {
    const double t = k * dt;
    const Eigen::Vector3d p = traj.position(t);
    const Eigen::Vector3d v = (traj.position(t + h) - traj.position(t - h)) / (2 * h);
    const Eigen::Vector3d a = (traj.position(t + h) - 2 * p + traj.position(t - h)) / (h * h);
    const Eigen::Quaterniond q = traj.orientation(t);
    const Eigen::Vector3d w = so3::logQuat(traj.orientation(t - h).conjugate() * traj.orientation(t + h)) / (2 * h);
    ImuSample s;
    s.t = t0 + static_cast<Timestamp>(k) * 5'000'000;
    s.gyro = w + bg;
    s.accel = q.conjugate() * (a - g) + ba;
    if (cfg.imu_noise) {
      s.gyro += cfg.noise.gyroscope_noise_density / std::sqrt(dt) * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
      s.accel += cfg.noise.accelerometer_noise_density / std::sqrt(dt) * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
    }
    seq.imu.push_back(s);

    if (k % 10 == 0) {
      TruthState ts{s.t, p, q, v, bg, ba};
      seq.truth.push_back(ts);
      FeatureFrame ff;
      ff.t = s.t;
      ff.frame_index = static_cast<std::uint32_t>(seq.frames.size());
      const Eigen::Isometry3d T_WB = Eigen::Translation3d(p) * q;
      const Eigen::Isometry3d T_C0W = (T_WB * seq.T_BC0).inverse(), T_C1W = (T_WB * seq.T_BC1).inverse();
      auto project = [&](const Eigen::Isometry3d& T_CW, std::size_t id, Eigen::Vector2d* px) {
        const Eigen::Vector3d pc = T_CW * landmarks[id];
        if (pc.z() < 0.3) return false;
        *px = Eigen::Vector2d(f * pc.x() / pc.z() + cx, f * pc.y() / pc.z() + cy);
        return px->x() >= 0 && px->x() < width && px->y() >= 0 && px->y() < height;
      };
      // Keep the tracks that are still visible first (like a tracker), then fill with new ones.
      std::vector<std::size_t> selected, fresh;
      for (std::size_t id = 0; id < landmarks.size(); ++id) {
        Eigen::Vector2d px;
        if (!project(T_C0W, id, &px)) continue;
        (tracked.count(id) ? selected : fresh).push_back(id);
      }
      std::shuffle(fresh.begin(), fresh.end(), rng);
      if (selected.size() > static_cast<std::size_t>(cfg.max_features)) selected.resize(static_cast<std::size_t>(cfg.max_features));
      for (std::size_t id : fresh) {
        if (selected.size() >= static_cast<std::size_t>(cfg.max_features)) break;
        selected.push_back(id);
      }
      tracked = std::unordered_set<std::size_t>(selected.begin(), selected.end());
      for (std::size_t id : selected) {
        for (int c = 0; c < 2; ++c) {
          Eigen::Vector2d px;
          if (!project(c == 0 ? T_C0W : T_C1W, id, &px)) continue;
          px += cfg.pixel_noise_px * Eigen::Vector2d(nd(rng), nd(rng));
          FeatureObservation o;
          o.track_id = id;
          o.camera_index = static_cast<std::uint8_t>(c);
          o.pixel = px;
          o.normalized = Eigen::Vector2d((px.x() - cx) / f, (px.y() - cy) / f);
          o.label = TrackLabel::kConsistent;
          ff.features.push_back(o);
        }
      }
      seq.frames.push_back(std::move(ff));
    }
    if (cfg.imu_noise) {
      bg += cfg.noise.gyroscope_random_walk * std::sqrt(dt) * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
      ba += cfg.noise.accelerometer_random_walk * std::sqrt(dt) * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
    }
  }
  return seq;
}

double ateAfterPositionYawAlignment(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt) {
  const std::size_t n = std::min(est.size(), gt.size());
  if (n == 0) return 0.0;
  Eigen::Vector3d me = Eigen::Vector3d::Zero(), mg = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    me += est[i];
    mg += gt[i];
  }
  me /= static_cast<double>(n);
  mg /= static_cast<double>(n);
  double sn = 0, cs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d e = est[i] - me, g = gt[i] - mg;
    sn += e.x() * g.y() - e.y() * g.x();
    cs += e.x() * g.x() + e.y() * g.y();
  }
  const Eigen::Matrix3d R = Eigen::AngleAxisd(std::atan2(sn, cs), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  double sq = 0;
  for (std::size_t i = 0; i < n; ++i) sq += (R * (est[i] - me) + mg - gt[i]).squaredNorm();
  return std::sqrt(sq / static_cast<double>(n));
}

}  // namespace mcvio::estimator::testing

namespace mcvio::estimator::testing {

RunResult runEstimator(const SyntheticSequence& seq, const EstimatorOptions& options) {
  SlidingWindowEstimator est(options, seq.T_BC0, seq.T_BC1, seq.focal_px, seq.noise);
  RunResult res;
  std::size_t k = 0;
  std::vector<Eigen::Vector3d> est_p, gt_p;
  std::vector<double> nees, times, cpu;
  for (std::size_t i = 0; i < seq.frames.size(); ++i) {
    while (k < seq.imu.size() && seq.imu[k].t <= seq.frames[i].t) est.addImu(seq.imu[k++]);
    timespec c0{}, c1{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c0);
    const EstimatorOutput out = est.addFrame(seq.frames[i]);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c1);
    res.outputs.push_back(out);
    if (!out.frame_accepted || out.status != EstimatorStatus::kTracking) continue;
    ++res.tracked_frames;
    times.push_back(out.timings.total_ms);
    cpu.push_back((c1.tv_sec - c0.tv_sec) * 1e3 + (c1.tv_nsec - c0.tv_nsec) * 1e-6);
    est_p.push_back(out.p_WB);
    gt_p.push_back(seq.truth[i].p);
    const Eigen::Vector3d e = out.p_WB - seq.truth[i].p;
    res.max_abs_position_error_m = std::max(res.max_abs_position_error_m, e.norm());
    if (out.covariance_valid) nees.push_back(e.dot(out.pose_covariance.topLeftCorner<3, 3>().ldlt().solve(e)));
  }
  res.resets = est.resetCount();
  res.ate_m = ateAfterPositionYawAlignment(est_p, gt_p);
  for (double x : nees) res.mean_position_nees += x / static_cast<double>(nees.size());
  if (!times.empty()) {
    std::sort(times.begin(), times.end());
    res.median_total_ms = times[times.size() / 2];
    std::sort(cpu.begin(), cpu.end());
    res.median_cpu_ms = cpu[cpu.size() / 2];
    res.p90_cpu_ms = cpu[cpu.size() * 9 / 10];
  }
  return res;
}

}  // namespace mcvio::estimator::testing
