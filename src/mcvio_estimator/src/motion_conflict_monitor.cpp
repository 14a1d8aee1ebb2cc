#include "mcvio/estimator/motion_conflict_monitor.hpp"

#include <algorithm>
#include <limits>

#include <Eigen/Dense>

#include "mcvio/estimator/imu_preintegrator.hpp"
#include "mcvio/estimator/so3.hpp"

namespace mcvio::estimator {

namespace {

conflict::RelativePoseSolver::Options solverOptions(const conflict::ConflictOptions& o) {
  conflict::RelativePoseSolver::Options s;
  s.observation_sigma_px = o.observation_sigma_px;
  s.huber_px = 2.0 * o.observation_sigma_px;
  s.outlier_px = 4.0 * o.observation_sigma_px;
  s.depth_weighting = o.vision_depth_weighting;
  return s;
}

conflict::RegionSplitDetector::Options splitOptions(const conflict::ConflictOptions& o) {
  conflict::RegionSplitDetector::Options s;
  s.chi2_threshold = o.split_chi2_threshold > 0 ? o.split_chi2_threshold : 1.0;  // 0: never called
  s.observation_sigma_px = o.observation_sigma_px;
  return s;
}

ConflictIntervalSmoother::Options smootherOptions(const conflict::ConflictOptions& o) {
  ConflictIntervalSmoother::Options s;
  s.settle_frames = o.smoothing_settle_frames;
  s.max_acceleration_correction = o.smoothing_max_acceleration_correction;
  s.held_acceleration_sigma = o.smoothing_held_acceleration_sigma;
  s.settled_velocity_sigma = o.smoothing_settled_velocity_sigma;
  return s;
}

Eigen::Isometry3d isometry(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = p;
  return T;
}

}  // namespace

MotionConflictMonitor::MotionConflictMonitor(const conflict::ConflictOptions& options, const conflict::RigGeometry& rig,
                                             const ImuNoiseParams& imu_noise, const Eigen::Vector3d& gravity,
                                             double min_depth_m, double max_depth_m)
    : options_(options),
      rig_(rig),
      T_C1C0_(rig.T_BC1.inverse() * rig.T_BC0),
      T_C0C1_(T_C1C0_.inverse()),
      imu_noise_(imu_noise),
      gravity_(gravity),
      min_depth_(min_depth_m),
      max_depth_(max_depth_m),
      pose_solver_(rig, solverOptions(options)),
      propagated_detector_(options.propagated_chi2_threshold),
      landmark_detector_(rig, options),
      split_detector_(rig, splitOptions(options), pose_solver_),
      tracker_(options.enter_frames, options.exit_frames, options.onset_min_score, options.onset_lookback_frames,
               options.exit_quiet_frames, options.exit_quiet_score),
      classifier_(options.selective_strikes, options.probation_agreeing_tests),
      smoother_(smootherOptions(options)) {}

void MotionConflictMonitor::reset() {
  history_.clear();
  have_pending_ = false;
  imu_dominated_ = false;
  drift_opened_ = false;
  entered_on_drift_ = false;
  drift_frames_ = 0;
  fast_drift_frames_ = 0;
  long_drift_frames_ = 0;
  have_reference_bias_ = false;
  last_disagreed_.clear();
  selective_bias_hold_ = false;
  first_seen_.clear();
  frames_since_reset_ = 0;
  frames_since_imu_exit_ = -1;
  frames_since_interval_ = -1;
  frames_after_conflict_ = -1;
  frontend_group_run_ = 0;
  backend_found_motion_ = false;
  whole_run_ = 0;
  tracker_.reset();
  classifier_.clear();
  secondary_.end();
  smoother_.cancel();
  active_since_ = 0;
}

Timestamp MotionConflictMonitor::oldestTimeNeeded() const {
  const Timestamp oldest = history_.empty() ? 0 : history_.front().t;
  return smoother_.active() ? std::min(oldest, smoother_.startTime()) : oldest;
}

ConflictIntervalSmoother::Result MotionConflictMonitor::smoothInterval(
    const ImuBuffer& imu, const ConflictIntervalSmoother::ReidentifiedEnd* reidentified,
    const ConflictIntervalSmoother::StartCovariance* start) {
  if (history_.empty()) {
    smoother_.cancel();
    return {};
  }
  // The second half of the settling frames: vision has had the first half to take the velocity over.
  std::vector<ConflictIntervalSmoother::SettledVelocity> settled;
  const std::size_t n = std::min(history_.size(), static_cast<std::size_t>(std::max(1, options_.smoothing_settle_frames / 2)));
  for (std::size_t i = history_.size() - n; i < history_.size(); ++i) settled.push_back({history_[i].t, history_[i].state.v});
  auto res = smoother_.finish(imu, imu_noise_, gravity_, history_.back().state.p, settled, reidentified, start);
  if (res.applied)
    for (auto& e : history_) e.state.p += res.shift;
  return res;
}

bool MotionConflictMonitor::triangulate(const Eigen::Vector2d& n0, const Eigen::Vector2d& n1, double* depth) const {
  // Depths d0, d1 along the two rays with d0 b0 - d1 R b1 = t in the least-squares sense, from the
  // 2x2 normal equations: a stereo pair's rays are never parallel enough to need a QR here.
  const Eigen::Vector3d b0(n0.x(), n0.y(), 1.0);
  const Eigen::Vector3d c1 = T_C0C1_.linear() * Eigen::Vector3d(n1.x(), n1.y(), 1.0);
  const Eigen::Vector3d& t = T_C0C1_.translation();
  const double a = b0.squaredNorm(), b = b0.dot(c1), c = c1.squaredNorm();
  const double det = a * c - b * b;
  if (!(det > 1e-12 * a * c)) return false;
  const double u = b0.dot(t), v = c1.dot(t);
  const double d0 = (c * u - b * v) / det, d1 = (b * u - a * v) / det;
  if (!(d0 > min_depth_ && d0 < max_depth_ && d1 > 0)) return false;
  const Eigen::Vector3d p_C1 = T_C1C0_ * (b0 * d0);
  if ((p_C1.head<2>() / p_C1.z() - n1).norm() * rig_.focal_px > 4.0 * options_.observation_sigma_px) return false;
  *depth = d0;
  return true;
}

void MotionConflictMonitor::triangulateAll(Entry* e) const {
  e->depth.clear();
  e->depth.reserve(e->cam0.size());
  for (const auto& [id, n0] : e->cam0) {
    const auto n1 = e->cam1.find(id);
    double d = 0;
    if (n1 != e->cam1.end() && triangulate(n0, n1->second, &d)) e->depth.emplace(id, d);
  }
}

std::vector<conflict::TrackedPoint> MotionConflictMonitor::collectPoints(const Entry& r, const ObservationMap& cam0,
                                                                         const Entry& k) const {
  std::vector<conflict::TrackedPoint> pts;
  pts.reserve(cam0.size());
  const double fb = rig_.focal_px * rig_.baseline();
  const double s = options_.stereo_sigma_px;
  for (const auto& [id, n0_k] : cam0) {
    const auto dr = r.depth.find(id);
    if (dr == r.depth.end()) continue;
    const double d = dr->second;
    const Eigen::Vector2d& n0_r = r.cam0.at(id);
    conflict::TrackedPoint p;
    p.track_id = id;
    const Eigen::Vector3d b0(n0_r.x(), n0_r.y(), 1.0);
    p.X_r = rig_.T_BC0 * (b0 * d);
    p.depth_r = d;
    p.ray_r = rig_.T_BC0.linear() * b0.normalized();
    p.depth_sigma_r = d * d * s / fb;
    p.n0_k = n0_k;
    const auto dk = k.depth.find(id);
    if (dk != k.depth.end()) {
      p.has_X_k = true;
      p.X_k = rig_.T_BC0 * (Eigen::Vector3d(n0_k.x(), n0_k.y(), 1.0) * dk->second);
      p.depth_sigma_k = dk->second * dk->second * s / fb;
    }
    pts.push_back(p);
  }
  return pts;
}

bool MotionConflictMonitor::imuMotion(const Entry& r, Timestamp t, const ImuBuffer& imu,
                                      conflict::RelativeMotion* motion, State* propagated,
                                      conflict::RelativeMotion* landmark_motion) const {
  std::vector<ImuSample> samples;
  if (!imu.extract(r.t, t, &samples) || samples.size() < 2) return false;
  const ImuBias bias = referenceBias(r);
  ImuPreintegrator pre(bias, imu_noise_);
  for (const auto& s : samples) pre.integrate(s);
  const double dt = pre.deltaTime();
  const Eigen::Matrix3d R_r = r.state.q.toRotationMatrix();
  const Eigen::Vector3d inertial = R_r.transpose() * (r.state.v * dt + 0.5 * gravity_ * dt * dt);
  motion->R = pre.deltaQ().toRotationMatrix();
  motion->t = inertial + pre.deltaP();
  const auto& C = pre.covariance();
  Eigen::Matrix<double, 6, 6> S = Eigen::Matrix<double, 6, 6>::Zero();
  S.block<3, 3>(0, 0) = C.block<3, 3>(0, 0);
  S.block<3, 3>(0, 3) = C.block<3, 3>(0, 6);
  S.block<3, 3>(3, 0) = C.block<3, 3>(6, 0);
  S.block<3, 3>(3, 3) = C.block<3, 3>(6, 6);
  // The state at r is an estimate: its velocity, attitude and biases spread the prediction.
  const double sv = options_.velocity_sigma_mps * dt, sa = options_.attitude_sigma_rad;
  const double sbg2 = options_.gyro_bias_sigma * options_.gyro_bias_sigma;
  const double sba2 = options_.accel_bias_sigma * options_.accel_bias_sigma;
  const Eigen::Matrix3d J_att = so3::hat(inertial);
  S.block<3, 3>(3, 3) += sv * sv * Eigen::Matrix3d::Identity() + sa * sa * J_att * J_att.transpose() +
                         sba2 * pre.dP_dba() * pre.dP_dba().transpose() + sbg2 * pre.dP_dbg() * pre.dP_dbg().transpose();
  S.block<3, 3>(0, 0) += sbg2 * pre.dR_dbg() * pre.dR_dbg().transpose();
  S.block<3, 3>(0, 3) += sbg2 * pre.dR_dbg() * pre.dP_dbg().transpose();
  S.block<3, 3>(3, 0) += sbg2 * pre.dP_dbg() * pre.dR_dbg().transpose();
  motion->covariance = S;
  if (landmark_motion != nullptr) {
    *landmark_motion = *motion;
    const double sl = options_.landmark_attitude_sigma_rad > 0 ? options_.landmark_attitude_sigma_rad : sa;
    landmark_motion->covariance.block<3, 3>(3, 3) += (sl * sl - sa * sa) * J_att * J_att.transpose();
  }
  pre.predict(r.state.p, r.state.q, r.state.v, bias, gravity_, &propagated->p, &propagated->q, &propagated->v);
  propagated->bias = bias;
  return motion->t.allFinite() && motion->R.allFinite();
}

std::size_t MotionConflictMonitor::trackReach(const ObservationMap& cam0, std::size_t max_frames) const {
  std::size_t reach = 0;
  for (auto it = history_.rbegin(); it != history_.rend() && reach < max_frames; ++it, ++reach) {
    int common = 0;
    for (const auto& [id, n] : cam0) common += it->cam0.count(id) != 0 ? 1 : 0;
    if (common < options_.min_landmarks_tested) break;
  }
  return reach;
}

bool MotionConflictMonitor::visionVelocity(std::size_t i, std::size_t span, const ImuBuffer& imu,
                                           Eigen::Vector3d* v) const {
  if (i < span || i >= history_.size()) return false;
  const Entry& a = history_[i - span];
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (std::size_t j = i - span + 1; j <= i; ++j) {
    if (!history_[j].vision_increment_valid) return false;
    T = T * history_[j].vision_increment;
  }
  std::vector<ImuSample> samples;
  if (!imu.extract(a.t, history_[i].t, &samples) || samples.size() < 2) return false;
  ImuPreintegrator pre(referenceBias(a), imu_noise_);
  for (const auto& s : samples) pre.integrate(s);
  const double dt = pre.deltaTime();
  if (!(dt > 0)) return false;
  // Vision's displacement is v_a dt + g dt^2 / 2 + R_a dP: solve for v_a, and let the IMU carry it
  // to frame i. (The mean vision velocity taken at mid-span is wrong under a shaking hand: it made
  // evidence out of nothing and kept the slow object's false interval open for good.)
  const Eigen::Matrix3d R_a = a.state.q.toRotationMatrix();
  const Eigen::Vector3d v_a = (R_a * (T.translation() - pre.deltaP()) - 0.5 * gravity_ * dt * dt) / dt;
  *v = v_a + gravity_ * dt + R_a * pre.deltaV();
  return v->allFinite();
}

void MotionConflictMonitor::solveVisionIncrement(const Entry& prev, const ImuBuffer& imu, Entry* cur) const {
  cur->vision_increment = Eigen::Isometry3d::Identity();
  cur->vision_increment_valid = false;
  conflict::RelativeMotion imu_prev;
  State ignored;
  if (!imuMotion(prev, cur->t, imu, &imu_prev, &ignored)) return;
  const auto all = collectPoints(prev, cur->cam0, *cur);
  std::vector<conflict::TrackedPoint> still;
  for (const auto& p : all)
    if (!classifier_.isMoving(p.track_id)) still.push_back(p);
  auto sol = pose_solver_.solve(still, imu_prev);
  // When the tracks not found moving cannot give a motion, the moving group is all vision has (a
  // cabin found moving before its interval turned IMU-dominated): measure against it, so the
  // secondary motion's chain of increments does not break.
  if (!sol.valid && still.size() < all.size()) sol = pose_solver_.solve(all, imu_prev);
  if (!sol.valid) return;
  cur->vision_increment.linear() = sol.motion.R;
  cur->vision_increment.translation() = sol.motion.t;
  cur->vision_increment_valid = true;
  cur->vision_rotation_covariance = sol.motion.covariance.block<3, 3>(0, 0);
}

MotionConflictMonitor::Decision MotionConflictMonitor::process(
    Timestamp t, const ObservationMap& cam0, const ObservationMap& cam1,
    const FrontendVerdicts& frontend, const ImuBuffer& imu) {
  Decision d;
  const auto mode = options_.mode;
  d.report.propagated_threshold = options_.propagated_chi2_threshold;
  pending_ = Entry{};
  pending_.t = t;
  pending_.cam0 = cam0;
  pending_.cam1 = cam1;
  triangulateAll(&pending_);
  have_pending_ = true;

  // Vision-only increment from the previous frame: the body's motion inside whatever it sees. Only
  // an IMU-dominated interval uses it (secondary motion, vision's rotation and velocity), and only
  // `imu` and `auto` open one: the reference VIO does not pay for it.
  const bool can_go_imu = mode == conflict::ResolutionMode::kImu || mode == conflict::ResolutionMode::kAuto;
  if (!history_.empty() && can_go_imu) solveVisionIncrement(history_.back(), imu, &pending_);

  const int H = options_.horizon_frames;
  bool evidence = false, whole = false, rotation_agrees = false, tested = false, drift_fired = false;
  bool drift_persisted = false;  // the drift has stood over its limit for the tracker's enter run
  bool group_seen = false;  // a partial conflict: a moving group next to static landmarks
  bool split_group = false;  // the region split's static side found this frame's partial group
  bool split_held = false;   // ... and has on split_min_frames frames in a row (a partial conflict)
  bool backend_motion = false;  // a coherent landmark group, or the region split held (a partial conflict)
  const int prev_split_run = split_run_;
  split_run_ = 0;
  double score = 0;  // evidence strength: the statistics relative to their thresholds
  int static_count = 0;
  std::vector<conflict::LandmarkConflictDetector::Verdict> verdicts;
  std::vector<std::uint64_t> moving_disagreeing;  // found moving, and still moving this frame
  const bool selective_active = mode == conflict::ResolutionMode::kSelective || mode == conflict::ResolutionMode::kAuto;
  if (static_cast<int>(history_.size()) >= H) {
    std::size_t r_index = history_.size() - static_cast<std::size_t>(H);
    Entry r = history_[r_index];
    // Inside an IMU-dominated interval the inertial velocity has drifted from what vision sees;
    // whether the conflict goes on is a question of acceleration, so take r's velocity from vision
    // (over the exit_velocity_frames before r, fewer once the speed hold has let go: a stopping
    // ride's braking should leave the test soon). When the view's tracks do not reach that far back
    // (every track is new once an occluder has gone) that velocity would measure the occluder, so
    // the velocity span and the test span share what the tracks do reach.
    if (imu_dominated_) {
      const auto want = static_cast<std::size_t>(speed_hold_engaged_ && !speed_hold_holding_
                                                     ? options_.exit_velocity_frames_after_hold
                                                     : options_.exit_velocity_frames);
      const std::size_t reach = trackReach(cam0, static_cast<std::size_t>(H) + want);
      std::size_t span = want;
      if (reach < static_cast<std::size_t>(H) + want && reach >= 4) {  // two frames each at least
        span = std::min(want, reach / 2);
        r_index = history_.size() - (reach - span);
        r = history_[r_index];
      }
      Eigen::Vector3d v_vis;
      if (visionVelocity(r_index, span, imu, &v_vis)) r.state.v = v_vis;
    }
    conflict::RelativeMotion imu_rel, imu_rel_landmarks;
    State propagated;
    if (imuMotion(r, t, imu, &imu_rel, &propagated, &imu_rel_landmarks)) {
      const auto pts = collectPoints(r, cam0, pending_);
      std::vector<conflict::TrackedPoint> still, moving;
      for (const auto& p : pts) (classifier_.isMoving(p.track_id) ? moving : still).push_back(p);
      const auto vis = pose_solver_.solve(still, imu_rel);
      if (vis.valid) {
        // Tracks already found moving, against the motion the others give: those still moving
        // hold the interval open below, also a slow object the IMU-referenced test never flags.
        if (!moving.empty())
          for (const auto& v : landmark_detector_.test(moving, vis.motion).verdicts)
            if (v.inconsistent) moving_disagreeing.push_back(v.track_id);
        tested = true;
        const auto prop = propagated_detector_.test(imu_rel, vis.motion);
        d.report.propagated_chi2 = prop.chi2;
        const Eigen::Matrix3d S_rot = imu_rel.covariance.block<3, 3>(0, 0) + vis.motion.covariance.block<3, 3>(0, 0);
        const Eigen::Vector3d e_rot = prop.error.head<3>();
        rotation_agrees = e_rot.dot(S_rot.ldlt().solve(e_rot)) < options_.rotation_chi2_threshold;
        whole = prop.fired;
        score = std::max(score, prop.chi2 / options_.propagated_chi2_threshold);
      }
      // ConflictOptions::landmark_attitude_sigma_rad, except inside an IMU-dominated interval,
      // where the held biases let the attitude drift.
      auto lm = landmark_detector_.test(pts, imu_dominated_ ? imu_rel : imu_rel_landmarks);
      // Region-split detector (ConflictOptions::split_chi2_threshold): two sides of the image
      // that move differently. Their static side's motion is a sharper reference than the IMU
      // prediction; a group it finds is a partial conflict (never whole-view: by construction
      // the reference side agrees). Inside an IMU-dominated interval nothing here is used.
      if (options_.split_chi2_threshold > 0 && !imu_dominated_) {
        const auto split = split_detector_.test(still, imu_rel, vis.valid ? vis.motion : imu_rel);
        d.report.split_chi2 = split.chi2;
        if (split.fired) {
          score = std::max(score, split.chi2 / options_.split_chi2_threshold);
          auto against_static = landmark_detector_.test(pts, split.static_motion);
          // Its static side agreeing with the IMU well inside the propagated test (a vehicle's
          // sides both disagree, the static one at 17 of 20 when its interval opens). That alone
          // tells a group beside a static world from a cabin, also on a frame where the
          // landmark test against that side finds no more than against the IMU (a slow object
          // whose tracks the frontend already removed; its interval then opened one frame
          // earlier, on the propagated test alone, and went IMU-dominated).
          split_group = split.static_chi2_imu < 0.5 * options_.propagated_chi2_threshold;
          split_run_ = split_group ? prev_split_run + 1 : 0;
          split_held = options_.split_min_frames > 0 && split_run_ >= options_.split_min_frames;
          if (against_static.inconsistent > lm.inconsistent && against_static.fraction < options_.whole_view_fraction) {
            lm = std::move(against_static);
            split_group_seen_ = true;
          }
        }
      }
      d.report.landmarks_tested = lm.tested;
      d.report.landmarks_inconsistent = lm.inconsistent;
      d.report.inconsistent_fraction = lm.fraction;
      d.report.coherence = lm.coherence;
      static_count = lm.tested - lm.inconsistent;
      if (lm.tested >= options_.min_landmarks_tested) {
        tested = true;
        score = std::max({score, lm.fraction / options_.whole_view_fraction,
                          std::min(static_cast<double>(lm.inconsistent) / options_.partial_min_count,
                                   lm.fraction / options_.partial_min_fraction)});
      }
      const bool partial = split_held ||
                           (lm.tested >= options_.min_landmarks_tested && lm.inconsistent >= options_.partial_min_count &&
                            lm.fraction >= options_.partial_min_fraction && lm.coherence >= options_.min_coherence);
      if (lm.tested >= options_.min_landmarks_tested && lm.fraction >= options_.whole_view_fraction) whole = true;
      group_seen = partial;
      backend_motion = partial || split_held;
      evidence = (whole || partial) && frames_since_reset_ >= options_.warmup_frames;
      verdicts = lm.verdicts;
    }
  }
  // The frontend detector (ConflictOptions::frontend_evidence) also sees tracks without stereo.
  d.report.frontend_checked = frontend.checked;
  d.report.frontend_inconsistent = static_cast<int>(frontend.inconsistent.size());
  if (options_.frontend_evidence && !imu_dominated_ && frontend.checked >= options_.min_landmarks_tested) {
    tested = true;
    const double labelled = static_cast<double>(frontend.inconsistent.size());
    const double fraction = labelled / static_cast<double>(frontend.checked);
    const double group_score = std::min(labelled / options_.frontend_min_count, fraction / options_.frontend_min_fraction);
    score = std::max(score, group_score);
    const bool labelled_group = labelled >= options_.frontend_min_count && fraction >= options_.frontend_min_fraction;
    frontend_group_run_ = labelled_group ? frontend_group_run_ + 1 : 0;
    // ConflictOptions::frontend_marginal_score: a group at the minima must show on two frames
    // before it counts towards opening an interval (inside one it still holds it open).
    const bool marginal = group_score < options_.frontend_marginal_score && frontend_group_run_ < 2 && !tracker_.inConflict();
    group_seen = group_seen || labelled_group;
    // frames_since_imu_exit_ >= 0: no reset since the last IMU-dominated exit, so the warm-up
    // running is that exit's (ConflictOptions::frontend_evidence_after_imu_exit).
    const bool warmed_up = frames_since_reset_ >= options_.warmup_frames ||
                           (options_.frontend_evidence_after_imu_exit && frames_since_imu_exit_ >= 0);
    if (labelled_group && !marginal && warmed_up) evidence = true;
  } else {
    frontend_group_run_ = 0;
  }
  // Bias-drift detector (ConflictOptions::bias_drift_sigmas): the estimator bending its
  // accelerometer bias to explain an acceleration vision does not see. Not inside an IMU-dominated
  // interval (the biases are held), nor before it arms (a moving start still converges), nor
  // beside a moving group (its pull bends the estimate too: the other detectors' case).
  if (options_.bias_drift_sigmas > 0 && !imu_dominated_ && !group_seen && have_reference_bias_ && !history_.empty() &&
      frames_since_reset_ >= std::max(options_.warmup_frames, options_.bias_drift_arm_frames)) {
    const double drift = (history_.back().state.bias.accel - reference_bias_.accel).norm();
    const double limit = options_.bias_drift_sigmas * options_.accel_bias_sigma;
    d.report.accel_bias_drift = drift;
    tested = true;
    // Only a drift over the limit scores: below it the estimate's noise sits at a third to a half
    // of the limit, and would backdate every interval's onset the whole lookback.
    if (drift >= limit) score = std::max(score, drift / limit);
    drift_frames_ = drift >= limit ? drift_frames_ + 1 : 0;
    // A brisk bend is a whole-view claim, so it needs the view auto trusts with one (at least
    // auto_min_tested_landmarks tested): an occluder filling the view leaves a few tracks, the
    // bias swings with them, and the landmark and frontend tests are the ones to judge it.
    const bool fast = options_.bias_drift_fast_factor > 0 && drift >= options_.bias_drift_fast_factor * limit &&
                      d.report.landmarks_tested >= options_.auto_min_tested_landmarks;
    fast_drift_frames_ = fast ? fast_drift_frames_ + 1 : 0;
    drift_fired = drift_frames_ >= options_.bias_drift_min_frames || fast_drift_frames_ >= options_.bias_drift_fast_frames;
    if (drift_fired) {
      whole = true;
      evidence = true;
      drift_persisted = drift_frames_ >= options_.enter_frames;
    }
  } else {
    drift_frames_ = 0;
    fast_drift_frames_ = 0;
  }
  // Slow bias drift (ConflictOptions::bias_drift_long_frames): the same bend against the estimate
  // of long frames before, when no interval lies in between. It opens the interval with that
  // estimate as the reference: the one above has followed the bend.
  const int long_frames = options_.bias_drift_long_frames;
  const bool long_anchor_valid = long_frames > 0 && !imu_dominated_ && !conflictActive() &&
                                 (frames_since_interval_ < 0 || frames_since_interval_ >= long_frames) &&
                                 frames_since_reset_ >= std::max(options_.warmup_frames, options_.bias_drift_arm_frames) + long_frames &&
                                 history_.size() > static_cast<std::size_t>(long_frames);
  const std::size_t long_anchor = long_anchor_valid ? history_.size() - 1 - static_cast<std::size_t>(long_frames) : 0;
  bool long_drift_fired = false;
  if (long_anchor_valid && !group_seen) {
    const double drift = (history_.back().state.bias.accel - history_[long_anchor].state.bias.accel).norm();
    const double limit = options_.bias_drift_long_sigmas * options_.accel_bias_sigma;
    tested = true;
    if (drift >= limit) score = std::max(score, drift / limit);
    long_drift_frames_ = drift >= limit ? long_drift_frames_ + 1 : 0;
    if (long_drift_frames_ >= options_.bias_drift_min_frames) {
      long_drift_fired = true;
      drift_fired = true;
      whole = true;
      evidence = true;
      drift_persisted = true;
      reference_bias_ = history_[long_anchor].state.bias;
      have_reference_bias_ = true;
    }
  } else {
    long_drift_frames_ = 0;
  }
  // Tracks already found moving and still in view keep a partial conflict open: selective
  // elimination has taken them out of the tests above, so without this the interval would close
  // while the pedestrian or the carried object is still there. Only a conflict that is open or
  // suspected: the frontend's labels eliminate tracks outside intervals too, and whether those
  // are evidence is frontend_evidence's to say. Only tracks that disagreed within the horizon
  // count: a laptop's tracks that slid onto the background as it left the view agree with the
  // static world (or cannot be tested until the horizon's reference frame has them), and held the
  // interval of a seed not used for tuning open 2.6 s after the laptop had gone. The frontend's
  // check runs on every frame, so its consistent label ends a track's memory at once.
  if (selective_active) {  // only the hold reads it
    ++frame_index_;
    for (const auto& v : verdicts)
      if (v.inconsistent) last_disagreed_[v.track_id] = frame_index_;
    for (const auto id : moving_disagreeing) last_disagreed_[id] = frame_index_;
    for (const auto id : frontend.inconsistent) last_disagreed_[id] = frame_index_;
    for (auto it = last_disagreed_.begin(); it != last_disagreed_.end();) {
      const bool agrees_now = options_.frontend_agreement_ends_hold && it->second != frame_index_ &&
                              frontend.consistent.count(it->first) != 0;
      it = frame_index_ - it->second > H || agrees_now ? last_disagreed_.erase(it) : std::next(it);
    }
    for (const auto& obs : cam0) first_seen_.emplace(obs.first, t);
    for (auto it = first_seen_.begin(); it != first_seen_.end();)
      it = cam0.count(it->first) == 0 ? first_seen_.erase(it) : std::next(it);
  }
  if (selective_active && !imu_dominated_ && frames_since_reset_ >= options_.warmup_frames && conflictActive()) {
    int moving_in_view = 0;
    for (const auto& obs : cam0)
      moving_in_view += classifier_.isMoving(obs.first) && last_disagreed_.count(obs.first) != 0 ? 1 : 0;
    if (moving_in_view >= options_.hold_moving_min_count &&
        moving_in_view >= options_.hold_moving_min_fraction * static_cast<double>(cam0.size()))
      evidence = true;
  }
  // The interval the bias-drift detector opened goes on while the conflicting frame accelerates
  // as fast as the drift limit (the horizon's tests miss a gentle ride as they did before), also
  // once the speed hold below has engaged: that acceleration is evidence, so the speed it gains
  // counts for the hold (a 40 s ride, still accelerating when the hold engaged at 0.5 m/s, ended
  // its interval mid-ride at 1.5 m/s without it). Until that acceleration can be measured over
  // bias_reference_lag_frames, the drift that opened the interval stands, but only before the
  // speed hold engaged (a 40 s ride whose secondary motion was lost 30 s in stayed open for good).
  // Only acceleration along the drift counts: a ride goes on the way the bias bent to explain it,
  // while a held bias a slow object had bent drifts the inertial estimate any way once the object
  // stops.
  if (options_.bias_drift_sigmas > 0 && imu_dominated_ && drift_opened_) {
    const std::size_t lag = static_cast<std::size_t>(std::max(1, options_.bias_reference_lag_frames));
    if (secondary_.valid() && history_.size() >= lag && history_[history_.size() - lag].secondary_valid) {
      const Entry& then = history_[history_.size() - lag];
      const double span = toSeconds(t - then.t);
      const double accel = span > 0 ? (secondary_.v_WS() - then.v_WS).dot(drift_direction_W_) / span : 0.0;
      if (accel >= options_.bias_drift_sigmas * options_.accel_bias_sigma) evidence = true;
    } else if (!speed_hold_engaged_) {
      evidence = true;
    }
  }
  // A conflicting frame still moving keeps its interval open (see hold_min_secondary_speed_mps).
  // Speed along the direction of the peak: the IMU-only estimate drifts sideways over a long ride.
  // Only speed the frame gained while the detectors saw it accelerate counts: an inertial estimate
  // drifting after a false alarm gains speed with no evidence, and must not hold its interval.
  // Nor does the peak turn round: past a stop, speed the other way is the inertial estimate
  // drifting on (a 40 s ride of the sweep stayed open 7 s after it stopped).
  if (imu_dominated_ && secondary_.valid()) {
    const Eigen::Vector3d& v = secondary_.v_WS();
    if (v.norm() > peak_secondary_velocity_.norm() && v.dot(peak_secondary_velocity_) >= 0) peak_secondary_velocity_ = v;
    const double peak = peak_secondary_velocity_.norm();
    const double along = peak > 0 ? v.dot(peak_secondary_velocity_) / peak : 0.0;
    if (evidence) evidence_secondary_speed_ = std::max(evidence_secondary_speed_, along);
    if (along >= options_.hold_min_secondary_speed_mps && along >= options_.hold_secondary_speed_fraction * peak &&
        along <= options_.hold_max_speed_gain * evidence_secondary_speed_) {
      evidence = true;
      speed_hold_engaged_ = true;
      speed_hold_holding_ = true;
    } else {
      speed_hold_holding_ = false;
    }
  }
  pending_.evidence = evidence;

  // Statistics before the warm-up ends are still settling: no build-up to go back over.
  const bool scored = tested && frames_since_reset_ >= options_.warmup_frames;
  const bool was_active = conflictActive();
  d.report.evidence_score = evidence ? std::max(score, 1.0) : scored ? score : std::numeric_limits<double>::quiet_NaN();
  tracker_.setQuietExitAllowed(imu_dominated_);  // ConflictOptions::exit_quiet_frames
  // A drift that fired after standing over its limit for enter_frames frames has had its
  // hysteresis: the tracker's run would only delay a vehicle's interval by one more frame.
  const auto state = tracker_.update(t, evidence, tested, d.report.evidence_score, drift_persisted);
  // Elimination acts only around detected conflicts, so a clean sequence keeps every landmark (and
  // the reference's accuracy); the frontend's labels may act on every frame if asked
  // (frontend_labels_outside_conflicts). Inside an IMU-dominated interval every landmark
  // disagrees with the inertial motion; that says nothing about which of them move.
  const bool in_interval = state != conflict::ConflictIntervalTracker::State::kNone;
  if (selective_active && !imu_dominated_) {
    if (in_interval)
      for (const auto& v : verdicts)
        if (classifier_.addVerdict(v.track_id, v.inconsistent)) d.eliminate.push_back(v.track_id);
    const bool after_conflict = frames_since_interval_ >= 0 && frames_since_interval_ < options_.frontend_labels_after_conflict_frames;
    const bool labels_outside =
        options_.frontend_labels_outside_conflicts &&
        (after_conflict || static_cast<int>(frontend.inconsistent.size()) >= options_.frontend_labels_outside_min_count);
    if (options_.use_frontend_labels && (in_interval || labels_outside))
      for (const auto id : frontend.inconsistent)
        if (cam0.count(id) != 0 && classifier_.addVerdict(id, true)) d.eliminate.push_back(id);
  }
  if (in_interval)
    frames_since_interval_ = 0;
  else if (frames_since_interval_ >= 0)
    ++frames_since_interval_;
  // Probation (onProbation) covers the tracks born on the frame before too: an occluder's first
  // tracks appear one frame before they can disagree, and their second observation pulled the
  // pose on the very frame that raised the suspicion.
  if (!was_active && state != conflict::ConflictIntervalTracker::State::kNone)
    active_since_ = history_.empty() ? t : history_.back().t;
  d.report.state = state == conflict::ConflictIntervalTracker::State::kConflict    ? ConflictReport::State::kConflict
                   : state == conflict::ConflictIntervalTracker::State::kSuspected ? ConflictReport::State::kSuspected
                                                                                    : ConflictReport::State::kNone;
  d.report.interval_start = tracker_.intervalStart();
  d.report.interval_onset = tracker_.intervalOnset();
  d.report.interval_end = tracker_.intervalEnd();

  if (state == conflict::ConflictIntervalTracker::State::kNone) {
    split_group_seen_ = false;
    backend_found_motion_ = false;
    whole_run_ = 0;
  } else {
    // A whole-view test firing alone on one frame, with a thin view, is not the motion found.
    whole_run_ = whole ? whole_run_ + 1 : 0;
    if (backend_motion || imu_dominated_ || whole_run_ >= options_.enter_frames) backend_found_motion_ = true;
  }
  if (tracker_.justEntered()) entered_on_drift_ = drift_fired;
  if (tracker_.justExited() && imu_dominated_) {
    if (options_.restart_on_exit && !history_.empty()) {
      const std::size_t last = history_.size() - 1;
      Entry from = history_[last];
      State inertial;
      conflict::RelativeMotion ignored;
      if (imuMotion(from, t, imu, &ignored, &inertial) &&
          visionVelocity(last, static_cast<std::size_t>(H), imu, &from.state.v) &&
          imuMotion(from, t, imu, &ignored, &d.exit_state)) {
        d.exit_state.bias = held_bias_;
        d.exit_velocity_jump_mps = (d.exit_state.v - inertial.v).norm();
        d.restart_on_exit = d.exit_velocity_jump_mps >= options_.restart_min_velocity_jump_mps;
      }
    }
    imu_dominated_ = false;
    drift_opened_ = false;
    smoother_.markExit();
    secondary_.end();
    classifier_.clear();
    // The frames of the interval carry the drifted inertial velocity, and vision needs a while to
    // correct it: a full warm-up before they serve as reference frames again (a shorter one
    // reopened a false interval after a vehicle ride).
    frames_since_reset_ = 0;
    frames_since_imu_exit_ = 0;
  }
  if (tracker_.inConflict() && !imu_dominated_) {
    // Auto: a conflict that opens whole-view without a static group (a closed cabin) is
    // IMU-dominated; one that opens partial (a pedestrian) or with a clear split stays selective
    // unless vision as a whole disagrees and too few landmarks still agree with the IMU (not once
    // the region split found the group while enough tracks in view are not found moving: see
    // split_group_seen_).
    // A clear split (a large disagreeing group next to enough landmarks that agree with the IMU,
    // e.g. a carried laptop or a vehicle's interior in front of a static street) is selective.
    // So is a group the region split found beside a side that agrees with the IMU: vision as a
    // whole may fail the propagated test on the same frame (pulled by the group before its tracks
    // are eliminated), but that side is static (a rendered slow object filling 44 % of the view went
    // IMU-dominated for 5.7 s: 0.133 m, selective 0.053 m).
    // An interval the bias drift opened may go IMU-dominated on a later frame the drift still
    // fires: a feature-level vehicle whose interval opened one frame sooner, on a frame that saw a
    // clear split, otherwise stayed selective for its whole ride (1.01 m instead of 0.04 m). Not
    // one the landmark or frontend tests opened: a drift inside it is the moving group's pull
    // (the injected overlay's, once its tracks were eliminated).
    const bool clear_split = (d.report.inconsistent_fraction >= options_.auto_split_fraction &&
                              static_count >= options_.auto_min_static_landmarks) ||
                             split_group;
    const bool enough_tested = d.report.landmarks_tested >= options_.auto_min_tested_landmarks;
    int unmoved_in_view = 0;
    for (const auto& obs : cam0) unmoved_in_view += classifier_.isMoving(obs.first) ? 0 : 1;
    const bool keep_selective = split_group_seen_ && unmoved_in_view >= options_.auto_min_static_landmarks;
    const bool want_imu = mode == conflict::ResolutionMode::kImu ||
                          (mode == conflict::ResolutionMode::kAuto && whole && enough_tested &&
                           (((tracker_.justEntered() || (drift_fired && entered_on_drift_)) && !clear_split) ||
                            (static_count < options_.auto_min_static_landmarks && !keep_selective)));
    if (want_imu) {
      imu_dominated_ = true;
      drift_opened_ = drift_fired;
      // The estimator explains an acceleration a vision does not see as the bias b + R^T a: the
      // bend, rotated into the world, points along the conflicting frame's acceleration.
      if (drift_fired)
        drift_direction_W_ =
            (history_.back().state.q * (history_.back().state.bias.accel - reference_bias_.accel)).normalized();
      speed_hold_engaged_ = false;
      speed_hold_holding_ = false;
      peak_secondary_velocity_.setZero();
      evidence_secondary_speed_ = 0;
      // The state before the evidence run: the reference frame of its first frame.
      std::size_t first = history_.size();
      for (std::size_t i = 0; i < history_.size(); ++i)
        if (history_[i].t >= tracker_.intervalStart()) {
          first = i;
          break;
        }
      std::size_t back = static_cast<std::size_t>(std::max(H, options_.rewind_frames));
      // A switch long after the interval opened (a carried object's selective interval whose
      // static view thinned out, no drift firing): the selective estimate up to the whole-view
      // evidence stands, so the rewind goes a horizon before that evidence's first frame, not
      // before the interval's start. Rewinding there replaced 5.6 s of a rendered self-occlusion's
      // selective estimate by the IMU alone (0.112 m; 0.015 m with this).
      if (!tracker_.justEntered() && !drift_fired && whole_run_ >= 1) {
        const std::size_t run_in_history = static_cast<std::size_t>(whole_run_ - 1);
        const std::size_t run_start = history_.size() >= run_in_history ? history_.size() - run_in_history : 0;
        if (run_start >= first + static_cast<std::size_t>(options_.rewind_frames)) {
          first = run_start;
          back = static_cast<std::size_t>(H);
        }
      }
      std::size_t idx = first >= back ? first - back : 0;
      // A slow drift began long before it fired: rewind_frames before the last estimate still
      // within a third of its limit of the reference, never before the reference's frame.
      if (long_drift_fired) {
        const double near = options_.bias_drift_long_sigmas * options_.accel_bias_sigma / 3.0;
        std::size_t bend = history_.size() - 1;
        while (bend > long_anchor && (history_[bend].state.bias.accel - reference_bias_.accel).norm() > near) --bend;
        const std::size_t rewind = static_cast<std::size_t>(options_.rewind_frames);
        idx = std::min(idx, std::max(long_anchor, bend >= rewind ? bend - rewind : 0));
      }
      const Entry* start = history_.empty() ? nullptr : &history_[idx];
      if (start == nullptr) {
        held_bias_ = ImuBias{};
      } else {
        held_bias_ = referenceBias(*start);
        State propagated;
        conflict::RelativeMotion ignored;
        if (options_.rewind_on_entry && imuMotion(*start, t, imu, &ignored, &propagated)) {
          d.rewind = true;
          d.rewind_state = propagated;
          d.rewind_t = start->t;
        }
        secondary_.begin(start->t, isometry(start->state.q, start->state.p));
        // The conflict window opens at the same state, unless the last one is still settling:
        // then both intervals are smoothed as one.
        if (smoother_.exited()) {
          smoother_.resumeInterval();
        } else {
          smoother_.begin(start->t, start->state.p, start->state.q, start->state.v, held_bias_);
          for (std::size_t i = idx + 1; i < history_.size(); ++i) smoother_.addFrame(history_[i].t, history_[i].state.q);
        }
        for (std::size_t i = idx + 1; i < history_.size(); ++i)
          secondary_.addVisionIncrement(history_[i].vision_increment, history_[i].vision_increment_valid);
      }
    }
  }
  d.imu_dominated = imu_dominated_;
  if (imu_dominated_ && options_.keep_consistent_rotation && rotation_agrees && pending_.vision_increment_valid) {
    d.vision_rotation = true;
    d.q_prev_cur = Eigen::Quaterniond(pending_.vision_increment.linear());
    const Eigen::Matrix3d info = pending_.vision_rotation_covariance.inverse();
    d.rotation_sqrt_information = info.llt().matrixU();
    if (!d.rotation_sqrt_information.allFinite()) d.vision_rotation = false;
  }
  // A selective interval whose test fell under thin_view_bias_hold_landmarks, or whose usable
  // tracks fell under thin_view_bias_hold_usable_tracks, holds the biases at the reference (as
  // IMU-dominated does) until it ends: the few static landmarks left behind a close occluder, or
  // beside a large slow object, cannot tell the accelerometer bias. So does one the region split
  // opened (split_bias_hold): the object's tracks, not yet flagged, pull the bias.
  if (!tracker_.inConflict()) {
    selective_bias_hold_ = false;
  } else if (selective_active && !imu_dominated_ && have_reference_bias_ && !selective_bias_hold_ &&
             (d.report.landmarks_tested < options_.thin_view_bias_hold_landmarks ||
              usableTracks(cam0) < options_.thin_view_bias_hold_usable_tracks ||
              (options_.split_bias_hold && split_held))) {
    selective_bias_hold_ = true;
    selective_held_bias_ = reference_bias_;
  }
  d.held_bias = held_bias_;
  d.hold_bias = imu_dominated_ || (frames_since_imu_exit_ >= 0 && frames_since_imu_exit_ < options_.exit_bias_hold_frames);
  if (selective_bias_hold_ && !imu_dominated_) {
    d.hold_bias = true;
    d.held_bias = selective_held_bias_;
  }
  d.suppress_zero_velocity = mode != conflict::ResolutionMode::kReference && tracker_.inConflict();
  switch (mode) {
    case conflict::ResolutionMode::kReference:
      d.report.resolution_mode = "reference";
      break;
    case conflict::ResolutionMode::kImu:
      d.report.resolution_mode = "imu";
      break;
    case conflict::ResolutionMode::kSelective:
      d.report.resolution_mode = "selective";
      break;
    case conflict::ResolutionMode::kAuto:
      d.report.resolution_mode = imu_dominated_ ? "auto:imu" : "auto:selective";
      break;
  }
  return d;
}

int MotionConflictMonitor::usableTracks(const ObservationMap& cam0) const {
  int usable = 0;
  for (const auto& obs : cam0) {
    if (classifier_.isMoving(obs.first)) continue;
    // The track's first frame stands in for its landmark's creation.
    const auto seen = first_seen_.find(obs.first);
    if (onProbation(obs.first, seen != first_seen_.end() ? seen->second : 0)) continue;
    ++usable;
  }
  return usable;
}

bool MotionConflictMonitor::onProbation(std::uint64_t track_id, Timestamp created) const {
  const auto mode = options_.mode;
  return options_.new_landmark_probation &&
         (mode == conflict::ResolutionMode::kSelective || mode == conflict::ResolutionMode::kAuto) && !imu_dominated_ &&
         conflictActive() && created >= active_since_ && !classifier_.isConfirmedStatic(track_id);
}

bool MotionConflictMonitor::biasSettled(std::size_t i) const {
  const ImuBias& b = history_[i].state.bias;
  const double max_a = options_.bias_reference_max_change_sigmas * options_.accel_bias_sigma;
  const double max_g = options_.bias_reference_max_change_sigmas * options_.gyro_bias_sigma;
  for (std::size_t j = i + 1; j < history_.size(); ++j) {
    const ImuBias& c = history_[j].state.bias;
    if ((c.accel - b.accel).norm() > max_a || (c.gyro - b.gyro).norm() > max_g) return false;
  }
  return true;
}

void MotionConflictMonitor::commit(const State& solved, ConflictReport* report) {
  if (!have_pending_) return;
  pending_.state = solved;
  if (secondary_.active()) {
    secondary_.addVisionIncrement(pending_.vision_increment, pending_.vision_increment_valid);
    secondary_.update(pending_.t, isometry(solved.q, solved.p));
  }
  if (report != nullptr && secondary_.valid()) {
    report->secondary_valid = true;
    report->p_WS = secondary_.T_WS().translation();
    report->q_WS = Eigen::Quaterniond(secondary_.T_WS().linear());
    report->v_WS = secondary_.v_WS();
  }
  pending_.secondary_valid = secondary_.valid();
  if (pending_.secondary_valid) pending_.v_WS = secondary_.v_WS();
  if (smoother_.active()) {
    smoother_.addFrame(pending_.t, solved.q);
    if (secondary_.valid())
      smoother_.setSecondary(pending_.t, solved.p, secondary_.T_WS().translation(),
                             Eigen::Quaterniond(secondary_.T_WS().linear()));
  }
  history_.push_back(std::move(pending_));
  have_pending_ = false;
  ++frames_since_reset_;
  if (frames_since_imu_exit_ >= 0) ++frames_since_imu_exit_;
  const std::size_t lag = static_cast<std::size_t>(options_.bias_reference_lag_frames);
  const bool in_conflict = tracker_.state() == conflict::ConflictIntervalTracker::State::kConflict;
  if (in_conflict)
    frames_after_conflict_ = 0;
  else if (frames_after_conflict_ >= 0)
    ++frames_after_conflict_;
  // Only biases estimated after the warm-up count: the first estimates are still settling. Nor,
  // when intervals hold biases, an estimate from the lag before an interval that has just closed:
  // it was bending before that interval was found, and an interval reopening soon would hold it
  // (an IMU-dominated exit restarts the warm-up anyway; a selective interval does not).
  // `reference` holds nothing and keeps its bend after the interval: a reference from before it
  // would count that bend as fresh evidence.
  const bool after_recent_interval = options_.mode != conflict::ResolutionMode::kReference &&
                                     frames_after_conflict_ >= 0 && frames_after_conflict_ <= static_cast<int>(lag);
  if (!in_conflict && !after_recent_interval && frames_since_reset_ > options_.warmup_frames + static_cast<int>(lag) &&
      history_.size() > lag && biasSettled(history_.size() - 1 - lag)) {
    reference_bias_ = history_[history_.size() - 1 - lag].state.bias;
    have_reference_bias_ = true;
  }
  const std::size_t keep =
      static_cast<std::size_t>(options_.horizon_frames + options_.enter_frames + options_.bias_reference_lag_frames +
                               options_.rewind_frames + std::max(0, options_.bias_drift_long_frames) +
                               std::max(options_.exit_velocity_frames, options_.exit_velocity_frames_after_hold) + 10);
  while (history_.size() > keep) history_.pop_front();
}

}  // namespace mcvio::estimator
