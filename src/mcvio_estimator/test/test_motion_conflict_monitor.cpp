// Unit tests of MotionConflictMonitor on constructed stereo-inertial sequences (no simulator):
// exact IMU samples of a known body trajectory, stereo observations projected from 3D points that
// are static, ride in a cabin with the device, or walk, and the true state committed as the solved
// one after every frame.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <vector>

#include <Eigen/Dense>

#include <gtest/gtest.h>

#include "mcvio/estimator/motion_conflict_monitor.hpp"

using namespace mcvio;
using estimator::ConflictReport;
using estimator::ImuBias;
using estimator::ImuBuffer;
using estimator::MotionConflictMonitor;

namespace {

constexpr Timestamp kStart = 1'000'000'000;       // not 0: interval_start 0 means "no interval"
constexpr Timestamp kFramePeriod = 50'000'000;    // 20 Hz stereo
constexpr Timestamp kImuPeriod = 5'000'000;       // 200 Hz IMU
constexpr double kNever = std::numeric_limits<double>::infinity();
const Eigen::Vector3d kGravity(0, 0, -9.81);

Timestamp frameTime(int k) { return kStart + k * kFramePeriod; }
double frameSeconds(int k) { return toSeconds(frameTime(k) - kStart); }

conflict::RigGeometry rig() {
  conflict::RigGeometry g;
  // cam0 looks along body x (EuRoC-like: camera z = body x), cam1 11 cm to its right.
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  g.T_BC0.linear() = R;
  g.T_BC1 = g.T_BC0;
  g.T_BC1.translation() = R * Eigen::Vector3d(0.11, 0, 0);
  g.focal_px = 458;
  return g;
}

/// Body motion without rotation: constant acceleration along x plus an optional smooth vertical
/// pulse a_z = A sin^2(pi (s - s0) / T) on [s0, s0 + T] (an elevator starting) and the same pulse
/// reversed from `brake_start_s` (the elevator stopping), all closed form.
struct Trajectory {
  Eigen::Vector3d v0{0.1, 0, 0};
  double accel_x = 0.05;
  double pulse_start_s = kNever, pulse_duration_s = 1.0, pulse_peak = 0.0;
  double brake_start_s = kNever;
  double second_pulse_start_s = kNever;  ///< a second ride: the same pulse again

  Eigen::Vector3d accel(double s) const {
    return {accel_x, 0,
            pulseAccel(s - pulse_start_s) - pulseAccel(s - brake_start_s) + pulseAccel(s - second_pulse_start_s)};
  }
  Eigen::Vector3d velocity(double s) const {
    return v0 + Eigen::Vector3d(accel_x * s, 0,
                                pulseVelocity(s - pulse_start_s) - pulseVelocity(s - brake_start_s) +
                                    pulseVelocity(s - second_pulse_start_s));
  }
  Eigen::Vector3d position(double s) const {
    return v0 * s + Eigen::Vector3d(0.5 * accel_x * s * s, 0,
                                    pulsePosition(s - pulse_start_s) - pulsePosition(s - brake_start_s) +
                                        pulsePosition(s - second_pulse_start_s));
  }

 private:
  // One pulse's contribution `tau` seconds after it starts (negative or -inf: before it).
  double pulseAccel(double tau) const {
    const double w = 2 * EIGEN_PI / pulse_duration_s;
    return tau > 0 && tau < pulse_duration_s ? 0.5 * pulse_peak * (1 - std::cos(w * tau)) : 0.0;
  }
  double pulseVelocity(double tau) const {
    const double c = std::clamp(tau, 0.0, pulse_duration_s), w = 2 * EIGEN_PI / pulse_duration_s;
    return 0.5 * pulse_peak * (c - std::sin(w * c) / w);
  }
  double pulsePosition(double tau) const {
    const double T = pulse_duration_s, w = 2 * EIGEN_PI / T;
    const double c = std::clamp(tau, 0.0, T), after = std::max(0.0, tau - T);
    return 0.5 * pulse_peak * (0.5 * c * c + (std::cos(w * c) - 1) / (w * w)) + 0.5 * pulse_peak * T * after;
  }
};

/// A tracked 3D point: static in the world, walking with `walk_velocity` over [walk_start_s,
/// walk_end_s), fixed in the body frame from `attach_s` on (the walls of a cabin carrying the
/// device), and out of view from `leave_s` on.
struct Point {
  std::uint64_t id = 0;
  Eigen::Vector3d X_W = Eigen::Vector3d::Zero();
  double walk_start_s = kNever, walk_end_s = kNever;
  Eigen::Vector3d walk_velocity = Eigen::Vector3d::Zero();
  double attach_s = kNever;
  double appear_s = -kNever;
  double leave_s = kNever;
  bool stereo = true;                  ///< false: seen by cam0 only (too close for a stereo match)
  bool frontend_inconsistent = false;  ///< the frontend labels it inconsistent while in view,
  double frontend_inconsistent_from_s = -kNever;  ///< from then on
  double frontend_consistent_from_s = kNever;     ///< until then

  Eigen::Vector3d world(double s) const {
    if (!(s > walk_start_s)) return X_W;
    return X_W + walk_velocity * (std::min(s, walk_end_s) - walk_start_s);
  }
  Eigen::Vector3d body(double s, const Trajectory& traj) const {
    const double at = std::min(s, attach_s);  // no rotation: body = world - position
    return world(at) - traj.position(at);
  }
};

struct Scenario {
  Trajectory traj;
  std::vector<Point> points;
  ImuBias imu_bias;  ///< the sensor's true bias, contained in the samples
  /// The bias committed as frame k's solved estimate; the true bias unless set.
  std::function<ImuBias(int)> committed_bias;
  /// The frontend's verdicts reach the monitor (every cam0 track checked); off: none, as from a
  /// frontend without the check.
  bool frontend_labels = false;
  /// Changes the state committed for frame k from the truth to what an estimator would commit
  /// after that decision (an inertial drift inside an IMU-dominated interval); none: the truth.
  std::function<void(int, const MotionConflictMonitor::Decision&, MotionConflictMonitor::State*)> commit_adjust;
};

/// Static points ahead of the device (it moves along body x, which cam0 looks along).
std::vector<Point> staticPoints(int count, std::uint64_t first_id, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(5.0, 10.0), y(-2.5, 2.5), z(-1.8, 1.8);
  std::vector<Point> pts;
  for (int i = 0; i < count; ++i) {
    Point p;
    p.id = first_id + static_cast<std::uint64_t>(i);
    p.X_W = Eigen::Vector3d(x(rng), y(rng), z(rng));
    pts.push_back(p);
  }
  return pts;
}

/// A person-sized rigid group of `count` points around `center`.
std::vector<Point> pedestrian(int count, std::uint64_t first_id, const Eigen::Vector3d& center, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Point> pts;
  for (int i = 0; i < count; ++i) {
    Point p;
    p.id = first_id + static_cast<std::uint64_t>(i);
    p.X_W = center + Eigen::Vector3d(0.2 * u(rng), 0.2 * u(rng), 0.6 * u(rng));
    pts.push_back(p);
  }
  return pts;
}

struct Frame {
  MotionConflictMonitor::Decision decision;  ///< report completed by commit()
  std::set<std::uint64_t> observed;          ///< tracks with a stereo observation
  std::set<std::uint64_t> on_probation;      ///< observed tracks held out (created when first observed)
  bool frontend_only = false;                ///< conflictFromFrontendOnly() after process()
  std::set<std::uint64_t> disagreed;         ///< observed tracks for which disagreedRecently()
};

/// Feeds `frames` frames of the scenario to a monitor: IMU up to the frame, process(), commit()
/// with the true state.
std::vector<Frame> run(const Scenario& sc, const conflict::ConflictOptions& options, int frames) {
  const auto g = rig();
  const Eigen::Isometry3d T_C0B = g.T_BC0.inverse(), T_C1B = g.T_BC1.inverse();
  MotionConflictMonitor monitor(options, g, ImuNoiseParams{}, kGravity, 0.1, 40.0);
  ImuBuffer imu;
  Timestamp next_imu = kStart;
  std::vector<Frame> out;
  std::map<std::uint64_t, Timestamp> first_seen;
  for (int k = 0; k < frames; ++k) {
    const Timestamp t = frameTime(k);
    for (; next_imu <= t; next_imu += kImuPeriod) {
      const double s = toSeconds(next_imu - kStart);
      ImuSample sample;
      sample.t = next_imu;
      sample.accel = sc.traj.accel(s) - kGravity + sc.imu_bias.accel;
      sample.gyro = sc.imu_bias.gyro;
      imu.add(sample, 0.1);
    }
    const double s = frameSeconds(k);
    MotionConflictMonitor::ObservationMap cam0, cam1;
    MotionConflictMonitor::FrontendVerdicts frontend;
    Frame f;
    for (const auto& p : sc.points) {
      if (s >= p.leave_s || s < p.appear_s) continue;
      const Eigen::Vector3d X_B = p.body(s, sc.traj);
      const Eigen::Vector3d c0 = T_C0B * X_B, c1 = T_C1B * X_B;
      if (c0.z() < 0.3 || c1.z() < 0.3) continue;
      const Eigen::Vector2d n0 = c0.head<2>() / c0.z(), n1 = c1.head<2>() / c1.z();
      // A 100 x 80 degree field of view.
      if (std::abs(n0.x()) > 1.2 || std::abs(n0.y()) > 0.85 || std::abs(n1.x()) > 1.2 || std::abs(n1.y()) > 0.85)
        continue;
      cam0[p.id] = n0;
      if (p.stereo) {
        cam1[p.id] = n1;
        f.observed.insert(p.id);
      }
      if (sc.frontend_labels) {
        ++frontend.checked;
        const bool labelled =
            p.frontend_inconsistent && s >= p.frontend_inconsistent_from_s && s < p.frontend_consistent_from_s;
        (labelled ? frontend.inconsistent : frontend.consistent).insert(p.id);
      }
    }
    f.decision = monitor.process(t, cam0, cam1, frontend, imu);
    f.frontend_only = monitor.conflictFromFrontendOnly();
    for (const auto& [id, n] : cam0)
      if (monitor.disagreedRecently(id)) f.disagreed.insert(id);
    for (const auto id : f.observed) {
      first_seen.emplace(id, t);
      if (monitor.onProbation(id, first_seen[id])) f.on_probation.insert(id);
    }
    MotionConflictMonitor::State truth;
    truth.p = sc.traj.position(s);
    truth.v = sc.traj.velocity(s);
    truth.bias = sc.committed_bias ? sc.committed_bias(k) : sc.imu_bias;
    if (sc.commit_adjust) sc.commit_adjust(k, f.decision, &truth);
    monitor.commit(truth, &f.decision.report);
    out.push_back(std::move(f));
  }
  return out;
}

conflict::ConflictOptions withMode(conflict::ResolutionMode mode) {
  conflict::ConflictOptions o;
  o.mode = mode;
  return o;
}

int firstFrame(const std::vector<Frame>& frames, const std::function<bool(const Frame&)>& pred) {
  for (std::size_t k = 0; k < frames.size(); ++k)
    if (pred(frames[k])) return static_cast<int>(k);
  return -1;
}

bool inConflict(const Frame& f) { return f.decision.report.state == ConflictReport::State::kConflict; }

// The cabin timeline: reference biases exist from frame 81 (warm-up 40 + lag 40); at kCabinFrame
// the doors close and the cabin starts a 1 s vertical pulse of 0.6 m/s^2.
constexpr int kCabinFrame = 100;
constexpr int kFramesAfterCabin = 40;
/// The IMU-vision disagreement grows from zero at the doors; the propagated detector crosses its
/// threshold 4 frames later (0.2 s, about 4 cm), the interval opens on the next.
constexpr int kMaxCabinEntryDelay = 6;

/// The committed accelerometer bias (z) ramping by `per_frame` from frame `start` up to `plateau`.
std::function<ImuBias(int)> accelBiasRamp(int start, double per_frame, double plateau) {
  return [=](int k) {
    ImuBias b;
    b.accel.z() = std::clamp(per_frame * (k - start), 0.0, plateau);
    return b;
  };
}

Scenario cabin(int points, int cabin_frame) {
  Scenario sc;
  sc.traj.pulse_start_s = frameSeconds(cabin_frame);
  sc.traj.pulse_peak = 0.6;
  sc.points = staticPoints(points, 0, 7);
  for (auto& p : sc.points) p.attach_s = frameSeconds(cabin_frame);
  sc.imu_bias.accel = Eigen::Vector3d(0.04, -0.03, 0.02);
  sc.imu_bias.gyro = Eigen::Vector3d(0.002, -0.001, 0.0015);
  return sc;
}

/// The cabin of kCabinFrame accelerating to 1.5 m/s in a 1 s pulse of 3 m/s^2, cruising, braking
/// from kBrakeFrame (the same pulse reversed) and standing still from kStopFrame on.
constexpr int kBrakeFrame = kCabinFrame + 60;
constexpr int kStopFrame = kCabinFrame + 80;
Scenario stoppingCabin() {
  Scenario sc = cabin(80, kCabinFrame);
  sc.traj.pulse_peak = 3.0;
  sc.traj.brake_start_s = frameSeconds(kBrakeFrame);
  return sc;
}

}  // namespace

TEST(MotionConflictMonitor, StaticWorldWithConsistentImuRaisesNoConflict) {
  Scenario sc;
  sc.points = staticPoints(80, 0, 1);
  sc.imu_bias.accel = Eigen::Vector3d(0.04, -0.03, 0.02);
  sc.imu_bias.gyro = Eigen::Vector3d(0.002, -0.001, 0.0015);
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto frames = run(sc, o, 160);
  // No evidence score while the statistics settle.
  for (int k = 0; k < o.warmup_frames; ++k) EXPECT_TRUE(std::isnan(frames[k].decision.report.evidence_score)) << k;
  for (int k = o.warmup_frames; k < static_cast<int>(frames.size()); ++k) {
    const auto& d = frames[k].decision;
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_GE(d.report.evidence_score, 0.0);
    EXPECT_LT(d.report.evidence_score, 0.1) << "the noise stays under onset_min_score";
    ASSERT_GE(frames[k].observed.size(), 30u);
    // The detectors ran: the horizon is filled and vision found the motion.
    EXPECT_GE(d.report.landmarks_tested, 30);
    EXPECT_GT(d.report.propagated_chi2, 0.0);
    EXPECT_LT(d.report.propagated_chi2, 1.0);
    EXPECT_EQ(d.report.landmarks_inconsistent, 0);
    EXPECT_EQ(d.report.state, ConflictReport::State::kNone);
    EXPECT_FALSE(d.imu_dominated);
    EXPECT_TRUE(d.eliminate.empty());
  }
}

TEST(MotionConflictMonitor, CabinInImuModeGoesImuDominatedWithRewindAndHeldBias) {
  const Scenario sc = cabin(80, kCabinFrame);
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kImu);
  const auto frames = run(sc, o, kCabinFrame + kFramesAfterCabin);
  ASSERT_GE(frames[kCabinFrame].observed.size(), 30u);
  for (int k = 0; k < kCabinFrame; ++k) EXPECT_FALSE(inConflict(frames[k])) << "frame " << k;

  const int entry = firstFrame(frames, [](const Frame& f) { return f.decision.imu_dominated; });
  ASSERT_GT(entry, kCabinFrame);
  EXPECT_LE(entry, kCabinFrame + kMaxCabinEntryDelay);
  // enter_frames frames of evidence: suspected, then the interval opens at the first of them.
  const int first_evidence = entry - o.enter_frames + 1;
  for (int k = first_evidence; k <= entry; ++k) {
    if (k < entry) {
      EXPECT_EQ(frames[k].decision.report.state, ConflictReport::State::kSuspected) << "frame " << k;
    }
    EXPECT_GE(frames[k].decision.report.evidence_score, 1.0) << "frame " << k;
  }
  EXPECT_LT(frames[first_evidence - 1].decision.report.evidence_score, 1.0);
  // In hindsight the interval starts where the score rose from the noise (the build-up), not later
  // than the first evidence.
  EXPECT_LE(frames[entry].decision.report.interval_onset, frameTime(first_evidence));
  EXPECT_GE(frames[entry].decision.report.interval_onset, frameTime(kCabinFrame));
  EXPECT_EQ(frames[first_evidence - 1].decision.report.state, ConflictReport::State::kNone);
  const auto& d = frames[entry].decision;
  EXPECT_EQ(d.report.state, ConflictReport::State::kConflict);
  EXPECT_EQ(d.report.interval_start, frameTime(first_evidence));
  EXPECT_EQ(d.report.resolution_mode, "imu");

  // The held bias is the one estimated before the conflict (here the true one).
  EXPECT_LT((d.held_bias.accel - sc.imu_bias.accel).norm(), 1e-12);
  EXPECT_LT((d.held_bias.gyro - sc.imu_bias.gyro).norm(), 1e-12);
  // The rewind goes rewind_frames before the evidence and propagates that state with the exact
  // IMU: it lands on the true state of this frame, not on what the cabin showed.
  ASSERT_TRUE(d.rewind);
  EXPECT_EQ(d.rewind_t, frameTime(first_evidence - o.rewind_frames));
  const double s = frameSeconds(entry);
  EXPECT_LT((d.rewind_state.p - sc.traj.position(s)).norm(), 1e-3);
  EXPECT_LT((d.rewind_state.v - sc.traj.velocity(s)).norm(), 1e-3);
  EXPECT_LT(d.rewind_state.q.angularDistance(Eigen::Quaterniond::Identity()), 1e-6);
  // Only the entry frame rewinds; the resolution holds while the cabin accelerates.
  for (int k = entry + 1; k < kCabinFrame + 20; ++k) {
    EXPECT_FALSE(frames[k].decision.rewind) << "frame " << k;
    EXPECT_TRUE(frames[k].decision.imu_dominated) << "frame " << k;
  }
}

// A cabin that pitches slowly agrees with the gyro over every horizon while its sum tilts the
// estimate, so by default vision's rotation stays out of an IMU-dominated interval; the option
// keeps it while it agrees (this cabin does not turn).
TEST(MotionConflictMonitor, ImuDominatedIntervalLeavesTheAttitudeToTheGyroUnlessAsked) {
  const Scenario sc = cabin(80, kCabinFrame);
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kImu);
  ASSERT_FALSE(o.keep_consistent_rotation);
  const auto gyro_only = run(sc, o, kCabinFrame + kFramesAfterCabin);
  o.keep_consistent_rotation = true;
  const auto with_vision = run(sc, o, kCabinFrame + kFramesAfterCabin);
  int dominated = 0, kept = 0;
  for (std::size_t k = 0; k < gyro_only.size(); ++k) {
    EXPECT_FALSE(gyro_only[k].decision.vision_rotation) << "frame " << k;
    ASSERT_EQ(gyro_only[k].decision.imu_dominated, with_vision[k].decision.imu_dominated) << "frame " << k;
    if (!with_vision[k].decision.imu_dominated) {
      EXPECT_FALSE(with_vision[k].decision.vision_rotation) << "frame " << k;
      continue;
    }
    ++dominated;
    if (!with_vision[k].decision.vision_rotation) continue;
    ++kept;
    // The cabin does not turn: the kept rotation is the identity within the pixel noise.
    EXPECT_LT(with_vision[k].decision.q_prev_cur.angularDistance(Eigen::Quaterniond::Identity()), 1e-3)
        << "frame " << k;
  }
  ASSERT_GE(dominated, 20);
  EXPECT_GE(kept, dominated * 9 / 10);
}

TEST(MotionConflictMonitor, CabinInReferenceModeIsReportedButNotResolved) {
  const auto frames = run(cabin(80, kCabinFrame), withMode(conflict::ResolutionMode::kReference),
                          kCabinFrame + kFramesAfterCabin);
  for (int k = 0; k < kCabinFrame; ++k) EXPECT_FALSE(inConflict(frames[k])) << "frame " << k;
  const int entry = firstFrame(frames, inConflict);
  EXPECT_GT(entry, kCabinFrame);
  EXPECT_LE(entry, kCabinFrame + kMaxCabinEntryDelay);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const auto& d = frames[k].decision;
    EXPECT_FALSE(d.imu_dominated) << "frame " << k;
    EXPECT_FALSE(d.rewind) << "frame " << k;
    EXPECT_TRUE(d.eliminate.empty()) << "frame " << k;
    EXPECT_EQ(d.report.resolution_mode, "reference");
  }
}

TEST(MotionConflictMonitor, AutoGoesImuDominatedInAWholeViewCabin) {
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto frames = run(cabin(80, kCabinFrame), o, kCabinFrame + kFramesAfterCabin);
  ASSERT_GE(static_cast<int>(frames[kCabinFrame].observed.size()), o.auto_min_tested_landmarks);
  for (int k = 0; k < kCabinFrame; ++k) EXPECT_FALSE(frames[k].decision.imu_dominated) << "frame " << k;
  const int entry = firstFrame(frames, [](const Frame& f) { return f.decision.imu_dominated; });
  ASSERT_GT(entry, kCabinFrame);
  // Whole view and enough landmarks in the test: IMU-dominated as the interval opens.
  EXPECT_LE(entry, kCabinFrame + 10);
  EXPECT_TRUE(frames[entry].decision.rewind);
  EXPECT_EQ(frames[entry].decision.report.resolution_mode, "auto:imu");
  EXPECT_GE(frames[entry].decision.report.landmarks_tested, o.auto_min_tested_landmarks);
}

// Too few landmarks in the test (a close occluder hides the scene): auto reports the conflict but
// keeps vision (selective) instead of trusting the IMU alone.
TEST(MotionConflictMonitor, AutoStaysSelectiveWithFewLandmarksInTheTest) {
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto frames = run(cabin(24, kCabinFrame), o, kCabinFrame + kFramesAfterCabin);
  ASSERT_LT(static_cast<int>(frames[kCabinFrame].observed.size()), o.auto_min_tested_landmarks);
  bool reported = false;
  for (const auto& f : frames) {
    EXPECT_FALSE(f.decision.imu_dominated);
    reported |= f.decision.report.state == ConflictReport::State::kConflict;
  }
  EXPECT_TRUE(reported) << "the cabin must still be reported";
}

namespace {

// A pedestrian of 12 points in front of 100 static ones (a partial conflict, never whole-view): walks sideways at 1 m/s from frame 100 for 1 s, stands for 2 s, leaves the view.
constexpr int kWalkFrame = 100, kStandFrame = 120, kLeaveFrame = 160, kPedestrianFrames = 190;
constexpr std::uint64_t kPedestrianId = 1000;
constexpr int kPedestrianPoints = 12;

/// The pedestrian's points (ids from `first_id`), in view from frame `appear_frame`.
std::vector<Point> walkingPedestrian(std::uint64_t first_id, std::uint32_t seed, int appear_frame) {
  auto walker = pedestrian(kPedestrianPoints, first_id, Eigen::Vector3d(5.5, -0.6, 0.0), seed);
  for (auto& p : walker) {
    p.walk_start_s = frameSeconds(kWalkFrame);
    p.walk_end_s = frameSeconds(kStandFrame);
    p.walk_velocity = Eigen::Vector3d(0, 1.0, 0);
    p.appear_s = appear_frame > 0 ? frameSeconds(appear_frame) : -kNever;
    p.leave_s = frameSeconds(kLeaveFrame);
  }
  return walker;
}

Scenario pedestrianScene() {
  Scenario sc;
  sc.points = staticPoints(100, 0, 3);
  const auto walker = walkingPedestrian(kPedestrianId, 5, 0);
  sc.points.insert(sc.points.end(), walker.begin(), walker.end());
  return sc;
}

bool isPedestrian(std::uint64_t id) { return id >= kPedestrianId; }

}  // namespace

TEST(MotionConflictMonitor, AutoStaysSelectiveAndEliminatesAFewMovingTracks) {
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto frames = run(pedestrianScene(), o, kPedestrianFrames);
  for (int k = kWalkFrame; k < kStandFrame; ++k) {
    int walkers = 0;
    for (const auto id : frames[k].observed) walkers += isPedestrian(id) ? 1 : 0;
    ASSERT_EQ(walkers, kPedestrianPoints) << "frame " << k;
  }
  std::set<std::uint64_t> eliminated;
  int last_elimination = -1;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const auto& d = frames[k].decision;
    EXPECT_FALSE(d.imu_dominated) << "frame " << k;
    EXPECT_NE(d.report.resolution_mode, "auto:imu") << "frame " << k;
    for (const auto id : d.eliminate) {
      EXPECT_TRUE(isPedestrian(id)) << "static track " << id << " eliminated at frame " << k;
      EXPECT_TRUE(eliminated.insert(id).second) << "track " << id << " eliminated twice";
      last_elimination = static_cast<int>(k);
    }
  }
  EXPECT_EQ(eliminated.size(), static_cast<std::size_t>(kPedestrianPoints));
  EXPECT_GE(last_elimination, kWalkFrame);
  EXPECT_LE(last_elimination, kWalkFrame + 4);
}

// The pedestrian's tracks, eliminated once found moving, hold the interval open while they still
// move against the motion the static tracks give. Standing, the pedestrian is no conflict (the
// simulator labels a body at rest as none): its tracks agree, and the interval closes a horizon
// after the last disagreement plus the exit hysteresis, long before it leaves the view.
TEST(MotionConflictMonitor, MovingTracksHoldTheIntervalOpenWhileTheyStillMove) {
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto frames = run(pedestrianScene(), o, kPedestrianFrames);
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GE(entry, kWalkFrame);
  ASSERT_LE(entry, kWalkFrame + 4);
  // Standing still, the pedestrian agrees with the IMU once the horizon has passed its walk.
  const int H = o.horizon_frames;
  EXPECT_EQ(frames[kStandFrame + H + 5].decision.report.landmarks_inconsistent, 0);
  for (int k = entry; k < kStandFrame + H; ++k) EXPECT_TRUE(inConflict(frames[k])) << "frame " << k;
  int closed = kStandFrame;
  while (closed < kPedestrianFrames && inConflict(frames[closed])) ++closed;
  // Later than the landmark test alone would close it (see the next test), by the hold's horizon.
  EXPECT_GT(closed, kStandFrame + H + o.exit_frames);
  EXPECT_LE(closed, kStandFrame + 2 * H + o.exit_frames);
  for (int k = closed; k < kPedestrianFrames; ++k) EXPECT_FALSE(inConflict(frames[k])) << "frame " << k;
}

// The hold has its own thresholds: with more moving tracks required than the pedestrian has, the
// interval closes as soon as the standing pedestrian agrees with the IMU.
TEST(MotionConflictMonitor, MovingTracksHoldOnlyAboveTheHoldThresholds) {
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  o.hold_moving_min_count = kPedestrianPoints + 1;
  const auto frames = run(pedestrianScene(), o, kPedestrianFrames);
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GE(entry, kWalkFrame);
  ASSERT_LE(entry, kWalkFrame + 4);
  int closed = entry;
  while (closed < kPedestrianFrames && inConflict(frames[closed])) ++closed;
  EXPECT_LE(closed, kStandFrame + o.horizon_frames + o.exit_frames + 2);
  for (int k = closed; k < kPedestrianFrames; ++k) EXPECT_FALSE(inConflict(frames[k])) << "frame " << k;
}

// The frontend checks every track on every frame: once it finds the standing pedestrian's tracks
// consistent, their earlier disagreements stop holding the interval, which closes when the
// horizon's landmark test has passed the walk (as without the hold). Off, the memory of the last
// disagreements holds it open up to a horizon longer.
TEST(MotionConflictMonitor, TracksTheFrontendFindsConsistentStopHoldingTheInterval) {
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  ASSERT_TRUE(o.frontend_agreement_ends_hold) << "the default";
  Scenario sc = pedestrianScene();
  sc.frontend_labels = true;
  for (auto& p : sc.points)
    if (isPedestrian(p.id)) {
      p.frontend_inconsistent = true;  // while it walks
      p.frontend_inconsistent_from_s = frameSeconds(kWalkFrame + 1);
      p.frontend_consistent_from_s = frameSeconds(kStandFrame);
    }
  const int H = o.horizon_frames;
  const auto closedAfter = [&](const conflict::ConflictOptions& options) {
    const auto frames = run(sc, options, kPedestrianFrames);
    const int entry = firstFrame(frames, inConflict);
    EXPECT_GE(entry, kWalkFrame);
    EXPECT_LE(entry, kWalkFrame + 4);
    EXPECT_EQ(frames[kStandFrame - 1].decision.report.frontend_inconsistent, kPedestrianPoints);
    EXPECT_EQ(frames[kStandFrame].decision.report.frontend_inconsistent, 0);
    int closed = kStandFrame;
    while (closed < kPedestrianFrames && inConflict(frames[closed])) ++closed;
    for (int k = closed; k < kPedestrianFrames; ++k) EXPECT_FALSE(inConflict(frames[k])) << "frame " << k;
    return closed;
  };
  const int closed = closedAfter(o);
  EXPECT_LE(closed, kStandFrame + H + o.exit_frames + 2);
  conflict::ConflictOptions off = o;
  off.frontend_agreement_ends_hold = false;
  const int closed_off = closedAfter(off);
  EXPECT_GT(closed_off, kStandFrame + H + o.exit_frames);
  EXPECT_GT(closed_off, closed);
}

// Behind a close occluder (24 points, all of them in the test: fewer than
// thin_view_bias_hold_landmarks) auto stays selective and holds the biases at the reference bias
// on every frame of the interval; with enough landmarks in the test, or with both thin-view
// options off, they stay free.
TEST(MotionConflictMonitor, AThinViewHoldsTheBiasesThroughASelectiveInterval) {
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const Scenario sc = cabin(24, kCabinFrame);
  const int n = kCabinFrame + kFramesAfterCabin;
  const auto frames = run(sc, o, n);
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GE(entry, kCabinFrame);
  ASSERT_LT(entry, n);
  for (int k = 0; k < n; ++k) {
    const auto& d = frames[k].decision;
    ASSERT_FALSE(d.imu_dominated) << "frame " << k;
    EXPECT_EQ(d.hold_bias, inConflict(frames[k])) << "frame " << k;
    if (!d.hold_bias) continue;
    EXPECT_LT((d.held_bias.accel - sc.imu_bias.accel).norm(), 1e-12) << "frame " << k;
    EXPECT_LT((d.held_bias.gyro - sc.imu_bias.gyro).norm(), 1e-12) << "frame " << k;
  }
  o.thin_view_bias_hold_landmarks = 0;
  o.thin_view_bias_hold_usable_tracks = 0;  // the cabin's tracks all move: none is usable either
  for (const auto& f : run(sc, o, n)) EXPECT_FALSE(f.decision.hold_bias);
  const auto walking = run(pedestrianScene(), withMode(conflict::ResolutionMode::kAuto), kPedestrianFrames);
  ASSERT_GE(firstFrame(walking, inConflict), kWalkFrame);
  for (const auto& f : walking) EXPECT_FALSE(f.decision.hold_bias);
}

namespace {

// A slow object filling the right of the view: 60 points 6-8 m ahead drift sideways at 0.2 m/s
// from frame 100 on, in front of 80 static points. Over the horizon each moves 10 cm, 6-8 px:
// inside the spread of an IMU prediction from a velocity known to 0.1 m/s (the estimate the
// object pulls; 3 px over the horizon), so the landmark test against the IMU never flags them.
constexpr int kDriftFrame = 100, kDriftFrames = 160;
constexpr std::uint64_t kSlowObjectId = 2000;

Scenario slowObjectScene(double speed_mps = 0.2) {
  Scenario sc;
  sc.points = staticPoints(80, 0, 13);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> x(6.0, 8.0), y(-2.4, -0.8), z(-1.5, 1.5);
  for (int i = 0; i < 60; ++i) {
    Point p;
    p.id = kSlowObjectId + static_cast<std::uint64_t>(i);
    p.X_W = Eigen::Vector3d(x(rng), y(rng), z(rng));
    p.walk_start_s = frameSeconds(kDriftFrame);
    p.walk_velocity = Eigen::Vector3d(0, speed_mps, 0);
    sc.points.push_back(p);
  }
  return sc;
}

}  // namespace

TEST(MotionConflictMonitor, ASlowObjectOnOneSideIsFoundByTheRegionSplit) {
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  o.velocity_sigma_mps = 0.1;
  const auto frames = run(slowObjectScene(), o, kDriftFrames);
  for (int k = o.warmup_frames; k < kDriftFrame; ++k) {
    EXPECT_FALSE(inConflict(frames[k])) << "frame " << k;
    EXPECT_GT(frames[k].decision.report.split_chi2, 0.0) << "frame " << k;
    EXPECT_LT(frames[k].decision.report.split_chi2, o.split_chi2_threshold) << "frame " << k;
  }
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GE(entry, kDriftFrame);
  EXPECT_LE(entry, kDriftFrame + o.horizon_frames);
  std::set<std::uint64_t> eliminated;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    EXPECT_FALSE(frames[k].decision.imu_dominated) << "frame " << k;
    for (const auto id : frames[k].decision.eliminate) eliminated.insert(id);
  }
  const auto wrong = std::count_if(eliminated.begin(), eliminated.end(), [](std::uint64_t id) { return id < kSlowObjectId; });
  EXPECT_LE(wrong, 2);
  EXPECT_GE(eliminated.size() - static_cast<std::size_t>(wrong), 40u);
  for (int k = entry; k < kDriftFrames; ++k) EXPECT_TRUE(inConflict(frames[k])) << "frame " << k;

  // Without the split only the IMU-referenced tests run: they never see the object.
  conflict::ConflictOptions off = o;
  off.split_chi2_threshold = 0;
  const auto without = run(slowObjectScene(), off, kDriftFrames);
  for (std::size_t k = 0; k < without.size(); ++k) {
    EXPECT_FALSE(inConflict(without[k])) << "frame " << k;
    EXPECT_EQ(without[k].decision.report.split_chi2, 0.0) << "frame " << k;
  }
}

// The slow object's interval is open when the static points it shares the view with go out of
// view, and 40 others come in: born in the conflict, they are on probation, so for a while the
// estimate is left with none of them although the object's 60 tracks keep the test full.
// thin_view_bias_hold_usable_tracks then holds the biases at the reference bias until the
// interval ends; with the option off, or with the static points staying, they stay free.
TEST(MotionConflictMonitor, FewUsableTracksBesideASlowObjectHoldTheBiases) {
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  o.velocity_sigma_mps = 0.1;
  ASSERT_EQ(o.thin_view_bias_hold_usable_tracks, 15) << "the default";
  o.split_bias_hold = false;  // the region split's own hold: ARegionSplitHeldHoldsTheBiases
  constexpr int kSwapFrame = kDriftFrame + 30;
  Scenario sc = slowObjectScene();
  for (auto& p : sc.points)
    if (p.id < kSlowObjectId) p.leave_s = frameSeconds(kSwapFrame);
  for (auto& p : staticPoints(40, 1000, 29)) {
    p.appear_s = frameSeconds(kSwapFrame);
    sc.points.push_back(p);
  }
  const auto frames = run(sc, o, kDriftFrames);
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GE(entry, kDriftFrame);
  ASSERT_LT(entry, kSwapFrame);
  const int held = firstFrame(frames, [](const Frame& f) { return f.decision.hold_bias; });
  EXPECT_GE(held, kSwapFrame);
  EXPECT_LE(held, kSwapFrame + 2);
  for (int k = 0; k < kDriftFrames; ++k) {
    const auto& d = frames[k].decision;
    ASSERT_FALSE(d.imu_dominated) << "frame " << k;
    if (k >= entry) {
      EXPECT_GE(d.report.landmarks_tested, o.thin_view_bias_hold_landmarks) << "frame " << k;
    }
    if (k >= held) {
      ASSERT_TRUE(inConflict(frames[k])) << "frame " << k;
      EXPECT_TRUE(d.hold_bias) << "frame " << k;
      EXPECT_LT((d.held_bias.accel - sc.imu_bias.accel).norm(), 1e-12) << "frame " << k;
    }
  }
  conflict::ConflictOptions off = o;
  off.thin_view_bias_hold_usable_tracks = 0;
  for (const auto& f : run(sc, off, kDriftFrames)) EXPECT_FALSE(f.decision.hold_bias);
  for (const auto& f : run(slowObjectScene(), o, kDriftFrames)) EXPECT_FALSE(f.decision.hold_bias);
}

TEST(MotionConflictMonitor, ARegionSplitHeldForSplitMinFramesIsAPartialConflict) {
  // The object at half the speed: its side's motion departs from the other's (chi-square 66-105)
  // while none of its tracks fails the landmark test on its own.
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  o.velocity_sigma_mps = 0.1;
  ASSERT_EQ(o.split_min_frames, 4);
  const auto frames = run(slowObjectScene(0.1), o, kDriftFrames);
  int held = -1;
  for (int k = kDriftFrame, fired = 0; k < kDriftFrames && held < 0; ++k) {
    fired = frames[k].decision.report.split_chi2 >= o.split_chi2_threshold ? fired + 1 : 0;
    if (fired == o.split_min_frames) held = k;
  }
  ASSERT_GT(held, kDriftFrame);
  for (int k = 0; k < held; ++k) ASSERT_FALSE(inConflict(frames[k])) << "frame " << k;
  EXPECT_EQ(frames[held].decision.report.state, ConflictReport::State::kSuspected);
  EXPECT_EQ(frames[held].decision.report.landmarks_inconsistent, 0) << "the split alone";
  EXPECT_EQ(firstFrame(frames, inConflict), held + o.enter_frames - 1);
  for (int k = held + o.enter_frames - 1; k < kDriftFrames; ++k) {
    EXPECT_TRUE(inConflict(frames[k])) << "frame " << k;
    EXPECT_FALSE(frames[k].decision.imu_dominated) << "partial: selective, frame " << k;
  }
  // Without it the same run of frames reports nothing.
  conflict::ConflictOptions off = o;
  off.split_min_frames = 0;
  const auto without = run(slowObjectScene(0.1), off, kDriftFrames);
  for (int k = 0; k < kDriftFrames; ++k) EXPECT_FALSE(inConflict(without[k])) << "frame " << k;
  for (int k = 0; k <= held; ++k)
    EXPECT_DOUBLE_EQ(without[k].decision.report.split_chi2, frames[k].decision.report.split_chi2) << "frame " << k;
}

// split_bias_hold: the interval the region split opened (the object's tracks still in the solve,
// none flagged yet) holds the biases at the reference from its first frame on. Off, the same
// interval leaves them free.
TEST(MotionConflictMonitor, ARegionSplitHeldHoldsTheBiases) {
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  o.velocity_sigma_mps = 0.1;
  ASSERT_TRUE(o.split_bias_hold) << "the default";
  const Scenario sc = slowObjectScene(0.1);
  conflict::ConflictOptions off = o;
  off.split_bias_hold = false;
  const auto free = run(sc, off, kDriftFrames);
  for (const auto& f : free) EXPECT_FALSE(f.decision.hold_bias);
  const auto frames = run(sc, o, kDriftFrames);
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GT(entry, kDriftFrame);
  EXPECT_EQ(entry, firstFrame(free, inConflict)) << "the hold changes no verdict";
  EXPECT_EQ(frames[entry].decision.report.landmarks_inconsistent, 0) << "opened by the split alone";
  for (int k = 0; k < kDriftFrames; ++k) {
    const auto& d = frames[k].decision;
    ASSERT_FALSE(d.imu_dominated) << "frame " << k;
    EXPECT_EQ(d.hold_bias, k >= entry) << "frame " << k;
    if (d.hold_bias) {
      EXPECT_LT((d.held_bias.accel - sc.imu_bias.accel).norm(), 1e-12) << "frame " << k;
    }
  }
}

namespace {

// A laptop carried 0.5 m in front of the device from frame 100 to 140: 60 tracks without stereo
// that the frontend labels inconsistent, covering all but 6 static points; when it leaves, 60
// static points it hid come into view as new tracks. Six static points are too few for both
// other detectors (the landmark detector needs min_landmarks_tested, the vision-only motion 8).
constexpr int kLaptopFrame = 100, kLaptopGoneFrame = 140, kLaptopFrames = 170;

Scenario laptopScene() {
  Scenario sc;
  sc.frontend_labels = true;
  sc.points = staticPoints(6, 0, 11);
  auto revealed = staticPoints(60, 100, 13);
  for (auto& p : revealed) p.appear_s = frameSeconds(kLaptopGoneFrame);
  sc.points.insert(sc.points.end(), revealed.begin(), revealed.end());
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double attach = frameSeconds(kLaptopFrame);
  for (int i = 0; i < 60; ++i) {
    Point p;
    p.id = 1000 + static_cast<std::uint64_t>(i);
    p.X_W = sc.traj.position(attach) + Eigen::Vector3d(0.5, 0.3 * u(rng), 0.2 * u(rng));
    p.attach_s = attach;
    p.appear_s = attach;
    p.leave_s = frameSeconds(kLaptopGoneFrame);
    p.stereo = false;
    p.frontend_inconsistent = true;
    sc.points.push_back(p);
  }
  return sc;
}

}  // namespace

// The landmark detector cannot test tracks without stereo, and 6 static points are too few for
// any other test: only the frontend's labels see the laptop. When it leaves, the revealed tracks
// are too new for the landmark detector's horizon, but the frontend checks them at once.
TEST(MotionConflictMonitor, FrontendLabelsDetectAnOccluderWithoutStereo) {
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto frames = run(laptopScene(), o, kLaptopFrames);
  for (int k = 0; k < kLaptopFrame; ++k) EXPECT_FALSE(inConflict(frames[k])) << "frame " << k;
  EXPECT_LT(frames[kLaptopFrame + 5].decision.report.landmarks_tested, o.min_landmarks_tested);
  EXPECT_EQ(frames[kLaptopFrame + 5].decision.report.frontend_inconsistent, 60);
  EXPECT_EQ(frames[kLaptopFrame + 5].decision.report.frontend_checked, 66);
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GE(entry, kLaptopFrame);
  EXPECT_LE(entry, kLaptopFrame + o.enter_frames - 1);
  for (int k = entry; k < kLaptopGoneFrame; ++k) {
    EXPECT_TRUE(inConflict(frames[k])) << "frame " << k;
    EXPECT_FALSE(frames[k].decision.imu_dominated) << "frame " << k;
  }
  int closed = kLaptopGoneFrame;
  while (closed < kLaptopFrames && inConflict(frames[closed])) ++closed;
  EXPECT_LE(closed, kLaptopGoneFrame + o.exit_frames - 1);
  EXPECT_LT(closed, kLaptopGoneFrame + o.horizon_frames) << "closed by the landmark detector, not the frontend's";
  for (int k = closed; k < kLaptopFrames; ++k) EXPECT_FALSE(inConflict(frames[k])) << "frame " << k;

  // Without the frontend detector nothing is tested while the laptop is there: no interval.
  conflict::ConflictOptions off = o;
  off.frontend_evidence = false;
  for (const auto& f : run(laptopScene(), off, kLaptopFrames)) EXPECT_FALSE(inConflict(f));
  // Below its thresholds (here: more labelled tracks than the laptop has) it raises nothing.
  conflict::ConflictOptions strict = o;
  strict.frontend_min_count = 61;
  for (const auto& f : run(laptopScene(), strict, kLaptopFrames)) EXPECT_FALSE(inConflict(f));
}

// frontend_conflict_keeps_history: the laptop's interval is found by the frontend's labels alone,
// so the estimator may keep the static landmarks' history (every laptop track has disagreed, no
// static one has); the slow object's is found by the region split and the landmark test, and
// never counts as the frontend's alone.
TEST(MotionConflictMonitor, AnIntervalOnlyTheFrontendFoundIsTold) {
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto frames = run(laptopScene(), o, kLaptopFrames);
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GE(entry, kLaptopFrame);
  for (int k = 0; k < kLaptopFrame; ++k) EXPECT_FALSE(frames[k].frontend_only) << "frame " << k;
  for (int k = entry; k < kLaptopGoneFrame; ++k) {
    ASSERT_TRUE(inConflict(frames[k])) << "frame " << k;
    EXPECT_TRUE(frames[k].frontend_only) << "frame " << k;
    for (const auto id : frames[k].disagreed) EXPECT_GE(id, 1000u) << "a static point, frame " << k;
    EXPECT_EQ(frames[k].disagreed.size(), 60u) << "frame " << k;
  }
  conflict::ConflictOptions slow = withMode(conflict::ResolutionMode::kAuto);
  slow.velocity_sigma_mps = 0.1;
  const auto split = run(slowObjectScene(), slow, kDriftFrames);
  int in_conflict = 0;
  for (const auto& f : split) {
    in_conflict += inConflict(f);
    EXPECT_FALSE(f.frontend_only);
  }
  EXPECT_GT(in_conflict, 10);
}

// frontend_marginal_score: tracks on an occluding edge slide against the background, and on clean
// rendered frames 8 of about 190 reached the frontend's minima on two frames in a row (8 of 100
// here: score 1). Such a group opens an interval only if it stays a third frame; a clear group
// (16 of 100: score 2) opens one after enter_frames, as before; with the option off (1) the two
// marginal frames open one too.
TEST(MotionConflictMonitor, FrontendLabelsAtTheirMinimaOnTwoFramesOpenNoInterval) {
  constexpr int kFrom = 60;
  auto scene = [&](int labelled, int frames_labelled) {
    Scenario sc;
    sc.points = staticPoints(100, 0, 5);
    sc.frontend_labels = true;
    for (int i = 0; i < labelled; ++i) {
      auto& p = sc.points[static_cast<std::size_t>(i)];
      p.frontend_inconsistent = true;
      p.frontend_inconsistent_from_s = frameSeconds(kFrom);
      p.frontend_consistent_from_s = frameSeconds(kFrom + frames_labelled);
    }
    return sc;
  };
  auto entry = [](const std::vector<Frame>& frames) { return firstFrame(frames, inConflict); };
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  ASSERT_EQ(o.frontend_min_count, 8);
  ASSERT_EQ(o.enter_frames, 2);
  ASSERT_GT(kFrom, o.warmup_frames);

  const auto two = run(scene(8, 2), o, 100);
  EXPECT_EQ(entry(two), -1);
  EXPECT_EQ(two[kFrom].decision.report.frontend_inconsistent, 8);
  for (std::size_t k = 0; k < two.size(); ++k)  // its second frame is evidence: suspected
    EXPECT_EQ(two[k].decision.report.state,
              static_cast<int>(k) == kFrom + 1 ? ConflictReport::State::kSuspected : ConflictReport::State::kNone)
        << "frame " << k;
  EXPECT_EQ(entry(run(scene(8, 3), o, 100)), kFrom + 2) << "on the marginal group's third frame";
  EXPECT_EQ(entry(run(scene(16, 2), o, 100)), kFrom + o.enter_frames - 1) << "a clear group as before";

  conflict::ConflictOptions off = o;
  off.frontend_marginal_score = 1.0;
  EXPECT_EQ(entry(run(scene(8, 2), off, 100)), kFrom + o.enter_frames - 1);
}

TEST(MotionConflictMonitor, FrontendLabelsEliminateAFewTracksOutsideAnyInterval) {
  // A walker entering the view: 4 of 84 tracks labelled, too few to be evidence of a conflict.
  Scenario sc;
  sc.points = staticPoints(84, 0, 1);
  sc.frontend_labels = true;
  for (int i = 0; i < 4; ++i) {
    sc.points[static_cast<std::size_t>(i)].frontend_inconsistent = true;
    sc.points[static_cast<std::size_t>(i)].appear_s = frameSeconds(60);
  }
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  ASSERT_TRUE(o.frontend_labels_outside_conflicts) << "the default";
  ASSERT_LT(4, o.frontend_min_count);
  auto eliminated = [](const std::vector<Frame>& frames, int* first_frame) {
    std::set<std::uint64_t> ids;
    *first_frame = -1;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      EXPECT_EQ(frames[k].decision.report.state, ConflictReport::State::kNone) << "frame " << k;
      for (const auto id : frames[k].decision.eliminate) {
        if (*first_frame < 0) *first_frame = static_cast<int>(k);
        ids.insert(id);
      }
    }
    return ids;
  };
  int first = -1;
  EXPECT_EQ(eliminated(run(sc, o, 100), &first), (std::set<std::uint64_t>{0, 1, 2, 3}));
  EXPECT_EQ(first, 60 + o.selective_strikes - 1) << "after selective_strikes labelled frames";

  // With frontend_labels_outside_min_count the frame's 4 labels must reach it.
  conflict::ConflictOptions four = o;
  four.frontend_labels_outside_min_count = 4;
  EXPECT_EQ(eliminated(run(sc, four, 100), &first), (std::set<std::uint64_t>{0, 1, 2, 3}));
  EXPECT_EQ(first, 60 + o.selective_strikes - 1);
  conflict::ConflictOptions five = o;
  five.frontend_labels_outside_min_count = 5;
  EXPECT_TRUE(eliminated(run(sc, five, 100), &first).empty());

  // Off, or in reference mode, the tracks stay until an interval opens.
  conflict::ConflictOptions off = o;
  off.frontend_labels_outside_conflicts = false;
  EXPECT_TRUE(eliminated(run(sc, off, 100), &first).empty());
  conflict::ConflictOptions reference = o;
  reference.mode = conflict::ResolutionMode::kReference;
  EXPECT_TRUE(eliminated(run(sc, reference, 100), &first).empty());
}

// frontend_labels_after_conflict_frames: two labelled tracks appear 10 frames after the laptop
// has gone, below frontend_labels_outside_min_count. Within the frames after the interval every
// label counts, so they are eliminated; past them, or with the option off, they stay.
TEST(MotionConflictMonitor, FrontendLabelsRightAfterAnIntervalEliminateEvenAFewTracks) {
  constexpr int kLateFrame = kLaptopGoneFrame + 10;
  Scenario sc = laptopScene();
  auto late = staticPoints(2, 2000, 23);
  for (auto& p : late) {
    p.appear_s = frameSeconds(kLateFrame);
    p.frontend_inconsistent = true;
  }
  sc.points.insert(sc.points.end(), late.begin(), late.end());
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  o.frontend_labels_outside_min_count = 3;
  auto lateEliminated = [&](const conflict::ConflictOptions& options, int* closed) {
    const auto frames = run(sc, options, kLaptopFrames);
    *closed = kLaptopGoneFrame;
    while (*closed < kLaptopFrames && frames[*closed].decision.report.state != ConflictReport::State::kNone) ++*closed;
    std::set<std::uint64_t> ids;
    for (int k = *closed; k < kLaptopFrames; ++k) {
      EXPECT_EQ(frames[k].decision.report.state, ConflictReport::State::kNone) << "frame " << k;
      for (const auto id : frames[k].decision.eliminate)
        if (id >= 2000) ids.insert(id);
    }
    return ids;
  };
  int closed = 0;
  EXPECT_TRUE(lateEliminated(o, &closed).empty()) << "2 labels, min count 3";
  ASSERT_LT(closed, kLateFrame);
  conflict::ConflictOptions after = o;
  after.frontend_labels_after_conflict_frames = kLateFrame - closed + 2;
  EXPECT_EQ(lateEliminated(after, &closed), (std::set<std::uint64_t>{2000, 2001}));
  conflict::ConflictOptions too_short = o;
  too_short.frontend_labels_after_conflict_frames = kLateFrame - closed;
  EXPECT_TRUE(lateEliminated(too_short, &closed).empty());
}

TEST(MotionConflictMonitor, HeldBiasComesFromASettledEstimateNotATransient) {
  // The reference bias lags bias_reference_lag_frames (40) behind the newest conflict-free frame:
  // with the cabin at frame 130 and the interval opening around 134, the lagged candidate is
  // about frame 93. The estimated accelerometer bias swings by 0.5 m/s^2 over frames 86..95 and
  // then settles at 0.01, so only the settling rule keeps the swing out of the held bias. (The
  // swing is along -x: along +x it would cancel part of the cabin's missing forward motion and
  // delay the detection past the swing.)
  constexpr int cabin_frame = 130;
  Scenario sc = cabin(80, cabin_frame);
  sc.imu_bias = ImuBias{};
  sc.committed_bias = [](int k) {
    ImuBias b;
    if (k >= 86 && k < 96) b.accel.x() = -0.5;
    if (k >= 96) b.accel.x() = 0.01;
    return b;
  };
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kImu);
  const auto frames = run(sc, o, cabin_frame + kFramesAfterCabin);
  // A swing in the estimate is no evidence either: the IMU prediction uses the settled reference.
  for (int k = 0; k < cabin_frame; ++k)
    EXPECT_EQ(frames[k].decision.report.state, ConflictReport::State::kNone) << "frame " << k;
  const int entry = firstFrame(frames, [](const Frame& f) { return f.decision.imu_dominated; });
  ASSERT_GT(entry, cabin_frame);
  ASSERT_LE(entry, cabin_frame + kMaxCabinEntryDelay);
  // The rewind starts rewind_frames before the evidence, inside the swing, yet holds the
  // pre-swing estimate.
  const auto& d = frames[entry].decision;
  EXPECT_LT(d.held_bias.accel.norm(), 1e-12) << "held accel bias " << d.held_bias.accel.transpose();
  ASSERT_TRUE(d.rewind);
  EXPECT_LT((d.rewind_state.v - sc.traj.velocity(frameSeconds(entry))).norm(), 1e-3);
}

TEST(MotionConflictMonitor, AnAccelerometerBiasBentPastItsLimitIsEvidence) {
  // A static world that vision and the IMU agree on, but the committed accelerometer bias (what the
  // estimator would report while it explains a gentle cabin acceleration away) ramps by 0.0045
  // m/s^2 per frame from kRampFrame. The reference bias freezes at the pre-ramp value (the ramp
  // moves more than 5 sigma per lag), so the drift, the last committed bias against it, passes
  // 2.5 x 0.02 m/s^2 in the report of frame kRampFrame + 13 (0.054) and is evidence from the
  // bias_drift_min_frames-th such frame on. That run is the hysteresis: the interval opens on it.
  constexpr int kRampFrame = 230;  // after the detector arms (bias_drift_arm_frames 200)
  Scenario sc;
  sc.points = staticPoints(80, 0, 11);
  sc.committed_bias = accelBiasRamp(kRampFrame, 0.0045, 1.0);
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  o.bias_drift_fast_factor = 0;  // the gentle path alone (the brisk one: next test)
  ASSERT_DOUBLE_EQ(o.bias_drift_sigmas, 2.5);
  const int total = kRampFrame + 60;
  const auto frames = run(sc, o, total);
  for (int k = 0; k < kRampFrame; ++k)
    ASSERT_EQ(frames[k].decision.report.state, ConflictReport::State::kNone) << "frame " << k;
  const int first_evidence = kRampFrame + 13 + o.bias_drift_min_frames - 1;
  const int opened = firstFrame(frames, inConflict);
  EXPECT_EQ(opened, first_evidence);
  EXPECT_GE(frames[opened].decision.report.accel_bias_drift, 0.05);
  EXPECT_NEAR(frames[kRampFrame + 10].decision.report.accel_bias_drift, 0.0405, 1e-9);

  // Nothing without the detector: the IMU prediction uses the reference bias, which is right.
  conflict::ConflictOptions off = o;
  off.bias_drift_sigmas = 0;
  for (const auto& f : run(sc, off, total)) EXPECT_FALSE(inConflict(f));
  // Nothing for a bend within the limit, one over it for too few frames, nor before the arming.
  sc.committed_bias = accelBiasRamp(kRampFrame, 0.0045, 0.045);
  for (const auto& f : run(sc, o, total)) EXPECT_FALSE(inConflict(f));
  sc.committed_bias = [&](int k) {
    ImuBias b;
    b.accel.z() = k >= kRampFrame && k < kRampFrame + o.bias_drift_min_frames - 1 ? 0.08 : 0.0;
    return b;
  };
  for (const auto& f : run(sc, o, total)) EXPECT_FALSE(inConflict(f));
  sc.committed_bias = accelBiasRamp(100, 0.0045, 1.0);
  const auto early = run(sc, o, 200);
  for (const auto& f : early) EXPECT_FALSE(inConflict(f));
}

TEST(MotionConflictMonitor, ASlowBiasDriftOpensAWholeViewIntervalRewoundToItsStart) {
  // A ride easing in over tens of seconds: the committed accelerometer bias ramps by 0.0004 m/s^2
  // per frame from kRampFrame, 0.016 m/s^2 over the 40-frame lag the reference bias follows it
  // with, so the bias-drift test against that reference never reaches its 0.05 m/s^2. Against
  // the estimate of bias_drift_long_frames (200) before, the drift passes 3.5 x 0.02 m/s^2 175
  // frames into the ramp; after bias_drift_min_frames such frames the interval opens,
  // IMU-dominated, holding the pre-ramp bias, and rewinds to rewind_frames before the last
  // estimate within a third of the limit (0.0233 m/s^2: ramp frame 58).
  constexpr int kRampFrame = 420;  // the slow test arms at 200 + 200 frames
  constexpr double kPerFrame = 0.0004;
  Scenario sc;
  sc.traj.v0 = Eigen::Vector3d(0.05, 0, 0);  // slow enough to keep the points ahead for 34 s
  sc.traj.accel_x = 0;
  sc.points = staticPoints(80, 0, 11);
  sc.committed_bias = accelBiasRamp(kRampFrame, kPerFrame, 1.0);
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  ASSERT_EQ(o.bias_drift_long_frames, 200);
  ASSERT_DOUBLE_EQ(o.bias_drift_long_sigmas, 3.5);
  const int total = kRampFrame + 260;
  const auto frames = run(sc, o, total);
  // The report of frame k tests the bias committed at k - 1 against the one of k - 201.
  const double limit = o.bias_drift_long_sigmas * o.accel_bias_sigma;
  int crossed = -1;
  for (int k = kRampFrame; k < total && crossed < 0; ++k)
    if (sc.committed_bias(k - 1).accel.z() - sc.committed_bias(k - 1 - o.bias_drift_long_frames).accel.z() >= limit)
      crossed = k;
  ASSERT_GT(crossed, kRampFrame + 170);
  const int opened = firstFrame(frames, inConflict);
  ASSERT_GT(opened, 0);
  for (int k = 0; k < opened; ++k) {
    ASSERT_EQ(frames[k].decision.report.state, ConflictReport::State::kNone) << "frame " << k;
    ASSERT_LT(frames[k].decision.report.accel_bias_drift, 0.05) << "the fast test stays quiet, frame " << k;
  }
  EXPECT_EQ(opened, crossed + o.bias_drift_min_frames - 1);
  const auto& d = frames[opened].decision;
  EXPECT_TRUE(d.imu_dominated) << "a whole-view conflict";
  EXPECT_LT(d.held_bias.accel.norm(), 1e-12) << "the bias before the ramp, not the followed one";
  ASSERT_TRUE(d.rewind);
  int bend = opened - 1;
  while (sc.committed_bias(bend).accel.z() > limit / 3.0) --bend;
  EXPECT_EQ(d.rewind_t, frameTime(bend - o.rewind_frames));
  EXPECT_LT(d.rewind_t, frameTime(kRampFrame + 20));
  EXPECT_GE(d.rewind_t, frameTime(opened - 1 - o.bias_drift_long_frames)) << "not before the reference";

  // Off: nothing. Nor for a bend that stays under the limit (a clean IMU's walk). A ramp from
  // frame 100 waits for the arming (frame 400), then for bias_drift_min_frames frames.
  conflict::ConflictOptions off = o;
  off.bias_drift_long_frames = 0;
  for (const auto& f : run(sc, off, total)) ASSERT_FALSE(inConflict(f));
  sc.committed_bias = accelBiasRamp(kRampFrame, kPerFrame, 0.065);
  for (const auto& f : run(sc, o, total)) ASSERT_FALSE(inConflict(f));
  sc.committed_bias = accelBiasRamp(100, kPerFrame, 1.0);
  EXPECT_EQ(firstFrame(run(sc, o, 460), inConflict), 400 + o.bias_drift_min_frames - 1);
}

TEST(MotionConflictMonitor, ABriskBiasBendIsEvidenceWithinTwoFrames) {
  // A vehicle starting briskly: the committed accelerometer bias bends by 0.02 m/s^2 per frame.
  // Its drift passes bias_drift_fast_factor x the limit (1.5 x 0.05) in the report of frame
  // kBendFrame + 4 (0.08); the second such frame is evidence, 15 frames before the gentle path.
  // The drift has stood over the limit itself for more than enter_frames frames by then, so that
  // frame opens the interval (a tracker's run of its own would wait one frame more).
  constexpr int kBendFrame = 230;
  Scenario sc;
  sc.points = staticPoints(80, 0, 11);
  sc.committed_bias = accelBiasRamp(kBendFrame, 0.02, 1.0);
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  ASSERT_DOUBLE_EQ(o.bias_drift_fast_factor, 1.5);
  ASSERT_EQ(o.bias_drift_fast_frames, 2);
  const int total = kBendFrame + 40;
  const auto frames = run(sc, o, total);
  for (int k = 0; k < kBendFrame; ++k)
    ASSERT_EQ(frames[k].decision.report.state, ConflictReport::State::kNone) << "frame " << k;
  int crossed = -1;
  for (int k = kBendFrame; k < total && crossed < 0; ++k)
    if (frames[k].decision.report.accel_bias_drift >= 0.075) crossed = k;
  ASSERT_GT(crossed, kBendFrame);
  const int opened = firstFrame(frames, inConflict);
  EXPECT_EQ(opened, crossed + o.bias_drift_fast_frames - 1);
  EXPECT_EQ(frames[opened - 1].decision.report.state, ConflictReport::State::kNone) << "not suspected first";
  EXPECT_TRUE(frames[opened].decision.imu_dominated) << "a whole-view conflict";
  EXPECT_LT(opened, crossed + o.bias_drift_min_frames) << "earlier than the gentle path";

  // Not for a bend that stays under 1.5 x the limit for fewer than bias_drift_min_frames, nor
  // for a single frame over it.
  sc.committed_bias = [&](int k) {
    ImuBias b;
    b.accel.z() = k >= kBendFrame && k < kBendFrame + o.bias_drift_min_frames - 1 ? 0.07 : 0.0;
    return b;
  };
  for (const auto& f : run(sc, o, total)) EXPECT_FALSE(inConflict(f));
  sc.committed_bias = [&](int k) {
    ImuBias b;
    b.accel.z() = k == kBendFrame ? 0.3 : 0.0;
    return b;
  };
  for (const auto& f : run(sc, o, total)) EXPECT_FALSE(inConflict(f));
  // Nor with too few landmarks in the test for a whole-view claim (an occluder filling the view):
  // then the bend waits for the gentle path.
  Scenario few = sc;
  few.points = staticPoints(24, 0, 11);
  few.committed_bias = accelBiasRamp(kBendFrame, 0.02, 1.0);
  const auto occluded = run(few, o, total);
  ASSERT_LT(occluded[kBendFrame + 5].decision.report.landmarks_tested, o.auto_min_tested_landmarks);
  const int opened_few = firstFrame(occluded, inConflict);
  EXPECT_TRUE(opened_few < 0 || opened_few >= kBendFrame + o.bias_drift_min_frames) << opened_few;
}

TEST(MotionConflictMonitor, ADriftIntervalStaysOpenOnlyWhileTheFrameAcceleratesAlongTheBend) {
  // A static world, the sensor's bias zero. The committed accelerometer bias stands `offset` in z
  // before kRampFrame (the reference bias the interval will hold), then ramps up by 0.0045 m/s^2
  // per frame until the bias-drift detector opens an IMU-dominated interval. Inside it the
  // committed (inertial) estimate accelerates at -offset: along the bend (+z) for a negative
  // offset, as a cabin the bend explained would, against it for a positive one, as after a slow
  // object that bent the bias and stopped. Both exceed the hold's limit (2.5 x 0.02 m/s^2).
  constexpr int kRampFrame = 230;
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  ASSERT_DOUBLE_EQ(o.bias_drift_sigmas * o.accel_bias_sigma, 0.05);
  const int total = kRampFrame + 140;
  auto run_with_offset = [&](double offset, int* opened) {
    Scenario sc;
    sc.points = staticPoints(80, 0, 11);
    sc.committed_bias = [=](int k) {
      ImuBias b;
      b.accel.z() = offset + std::max(0, k - kRampFrame) * 0.0045;
      return b;
    };
    auto since = std::make_shared<int>(-1);
    sc.commit_adjust = [=](int k, const MotionConflictMonitor::Decision& d, MotionConflictMonitor::State* s) {
      if (!d.imu_dominated) {
        *since = -1;
        return;
      }
      if (*since < 0) *since = k;
      const double dt = frameSeconds(k) - frameSeconds(*since);
      s->v.z() = -offset * dt;
      s->p.z() = -0.5 * offset * dt * dt;
    };
    const auto frames = run(sc, o, total);
    *opened = firstFrame(frames, [](const Frame& f) { return f.decision.imu_dominated; });
    return frames;
  };
  int opened_along = -1, opened_against = -1;
  const auto along = run_with_offset(-0.08, &opened_along);
  const auto against = run_with_offset(0.08, &opened_against);
  for (const int opened : {opened_along, opened_against}) {
    ASSERT_GT(opened, kRampFrame) << "the offset alone is no evidence";
    ASSERT_LT(opened, kRampFrame + 60);
  }
  // Along the bend the interval holds until the end (the speed hold would need 0.5 m/s: 6 s).
  for (int k = opened_along; k < total; ++k) EXPECT_TRUE(along[k].decision.imu_dominated) << "frame " << k;
  // Against it the interval closes soon after the acceleration can be measured (40 frames).
  const int closed = firstFrame(against, [&](const Frame& f) {
    return &f - against.data() > opened_against && !f.decision.imu_dominated;
  });
  ASSERT_GT(closed, opened_against);
  EXPECT_LE(closed, opened_against + o.bias_reference_lag_frames + o.exit_frames + 5);
}

TEST(MotionConflictMonitor, ABiasBendWithAMovingGroupInViewIsLeftToTheOtherDetectors) {
  // The same bend while the frontend labels a group of tracks inconsistent (a pedestrian whose pull
  // bends the whole estimate): the drift is not reported, the frontend detector opens a partial
  // (selective) interval instead of an IMU-dominated one.
  constexpr int kRampFrame = 230;
  Scenario sc;
  sc.points = staticPoints(80, 0, 11);
  auto group = pedestrian(20, 1000, Eigen::Vector3d(12, 0.5, 0), 5);
  for (auto& p : group) {
    p.appear_s = frameSeconds(kRampFrame);
    p.frontend_inconsistent = true;
  }
  sc.points.insert(sc.points.end(), group.begin(), group.end());
  sc.frontend_labels = true;
  sc.committed_bias = accelBiasRamp(kRampFrame, 0.0045, 1.0);
  const auto frames = run(sc, withMode(conflict::ResolutionMode::kAuto), kRampFrame + 60);
  for (int k = kRampFrame; k < kRampFrame + 60; ++k) {
    EXPECT_EQ(frames[k].decision.report.accel_bias_drift, 0.0) << "frame " << k;
    EXPECT_FALSE(frames[k].decision.imu_dominated) << "frame " << k;
  }
  EXPECT_GE(firstFrame(frames, inConflict), kRampFrame);
}

TEST(MotionConflictMonitor, ACabinCruisingAtSteadySpeedKeepsItsIntervalOpen) {
  // A 1 s pulse of 3 m/s^2 peak, then the cabin cruises at 1.5 m/s: no acceleration left for the
  // detectors, but the secondary motion (the cabin in the world) still moves.
  Scenario sc = cabin(80, kCabinFrame);
  sc.traj.pulse_peak = 3.0;
  const int frames_total = kCabinFrame + 160;
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kImu);
  const auto held = run(sc, o, frames_total);
  const int entry = firstFrame(held, [](const Frame& f) { return f.decision.imu_dominated; });
  ASSERT_GT(entry, kCabinFrame);
  ASSERT_LE(entry, kCabinFrame + kMaxCabinEntryDelay);
  for (int k = entry; k < frames_total; ++k) {
    EXPECT_TRUE(held[k].decision.imu_dominated) << "frame " << k;
    EXPECT_TRUE(inConflict(held[k])) << "frame " << k;
  }
  // The cabin's speed is what holds it: its estimate is the cruise speed.
  const auto& last = held.back().decision.report;
  ASSERT_TRUE(last.secondary_valid);
  EXPECT_NEAR(last.v_WS.z(), 1.5, 0.05);

  // Without the hold the interval ends mid-cruise, once the acceleration test is satisfied.
  o.hold_min_secondary_speed_mps = 1e9;
  const auto released = run(sc, o, frames_total);
  const int exit = firstFrame(released, [&](const Frame& f) {
    return &f - released.data() > entry && !f.decision.imu_dominated;
  });
  EXPECT_GT(exit, entry) << "the interval should close while the cabin cruises";
}

TEST(MotionConflictMonitor, AStoppingCabinLeavesTheTestSoonerOnceTheSpeedHoldLetsGo) {
  // The cruising cabin brakes after 2 s (the same pulse reversed) and stands still from then on.
  // Once its speed falls below the hold's share of the peak, vision's velocity is taken over
  // exit_velocity_frames_after_hold frames, so the braking leaves the acceleration test sooner.
  const Scenario sc = stoppingCabin();
  const int stop_frame = kStopFrame;
  ASSERT_NEAR(sc.traj.velocity(frameSeconds(stop_frame)).z(), 0.0, 1e-9);
  const int frames_total = stop_frame + 80;
  auto exitFrame = [&](int after_hold_frames, int* entry) {
    conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kImu);
    o.exit_velocity_frames_after_hold = after_hold_frames;
    const auto frames = run(sc, o, frames_total);
    *entry = firstFrame(frames, [](const Frame& f) { return f.decision.imu_dominated; });
    const int e = *entry;
    return firstFrame(frames, [&](const Frame& f) { return &f - frames.data() > e && !f.decision.imu_dominated; });
  };
  int entry_short = -1, entry_long = -1;
  const int exit_short = exitFrame(5, &entry_short);
  const int exit_long = exitFrame(10, &entry_long);  // = exit_velocity_frames: the option off
  ASSERT_GT(entry_short, kCabinFrame);
  ASSERT_LE(entry_short, kCabinFrame + kMaxCabinEntryDelay);
  EXPECT_EQ(entry_long, entry_short);
  // Both stay IMU-dominated through the cruise and the braking, ...
  EXPECT_GE(exit_short, stop_frame);
  EXPECT_GE(exit_long, stop_frame);
  // ... and the short span ends the interval sooner after the stop.
  EXPECT_LE(exit_short, exit_long - 3) << "short " << exit_short << ", long " << exit_long;
}

// Once the cabin stands, its evidence score falls far below the thresholds within a few frames:
// exit_quiet_frames such frames close the IMU-dominated interval before exit_frames clean ones
// would, never before the cabin has stopped.
TEST(MotionConflictMonitor, AStoppedCabinClosesItsIntervalOnQuietFrames) {
  const Scenario sc = stoppingCabin();
  const int stop_frame = kStopFrame;
  const int frames_total = stop_frame + 80;
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kImu);
  ASSERT_EQ(o.exit_quiet_frames, 2) << "the default";
  auto exitFrame = [&](int quiet_frames, std::vector<Frame>* out) {
    conflict::ConflictOptions q = o;
    q.exit_quiet_frames = quiet_frames;
    *out = run(sc, q, frames_total);
    const auto& frames = *out;
    const int entry = firstFrame(frames, [](const Frame& f) { return f.decision.imu_dominated; });
    EXPECT_GT(entry, kCabinFrame);
    EXPECT_LE(entry, kCabinFrame + kMaxCabinEntryDelay);
    return firstFrame(frames, [&](const Frame& f) { return &f - frames.data() > entry && !inConflict(f); });
  };
  std::vector<Frame> quiet_run, counted_run;
  const int quiet = exitFrame(o.exit_quiet_frames, &quiet_run);
  const int counted = exitFrame(0, &counted_run);
  EXPECT_GE(quiet, stop_frame);
  EXPECT_LT(quiet, counted);
  EXPECT_GE(quiet, counted - (o.exit_frames - o.exit_quiet_frames));
  // The frames that closed it scored under exit_quiet_score.
  for (int k = quiet - o.exit_quiet_frames + 1; k <= quiet; ++k)
    EXPECT_LT(quiet_run[k].decision.report.evidence_score, o.exit_quiet_score) << "frame " << k;
}

TEST(MotionConflictMonitor, AnInertialDriftPastTheStopDoesNotHoldTheInterval) {
  // The cruising cabin brakes to a stop, but the committed (inertial) estimate keeps braking: from
  // the start of the braking it loses 2.5 m/s per second more than the cabin, until it goes down
  // at 1.7 m/s (1.6 s after the stop), faster than the cruise was, slower than the 1.25 x that the
  // hold allows. That speed is the cabin's direction reversed: it must not become the peak the
  // speed hold measures against (a 40 s ride of the sweep, held bias 0.04 m/s^2 off, stayed
  // IMU-dominated 7 s after it stopped).
  Scenario sc = stoppingCabin();
  const int brake_frame = kBrakeFrame, stop_frame = kStopFrame;
  constexpr double kDrift = 2.5, kDriftSpeed = 3.2;  // m/s^2, m/s (1.5 of the cruise, 1.7 beyond)
  sc.commit_adjust = [=](int k, const MotionConflictMonitor::Decision& d, MotionConflictMonitor::State* s) {
    if (!d.imu_dominated || k < brake_frame) return;
    const double dt = frameSeconds(k) - frameSeconds(brake_frame), ramp = kDriftSpeed / kDrift;
    s->v.z() -= kDrift * std::min(dt, ramp);
    s->p.z() -= dt < ramp ? 0.5 * kDrift * dt * dt : 0.5 * kDriftSpeed * ramp + kDriftSpeed * (dt - ramp);
  };
  const int frames_total = stop_frame + 100;
  const auto frames = run(sc, withMode(conflict::ResolutionMode::kImu), frames_total);
  const int entry = firstFrame(frames, [](const Frame& f) { return f.decision.imu_dominated; });
  ASSERT_GT(entry, kCabinFrame);
  ASSERT_LE(entry, kCabinFrame + kMaxCabinEntryDelay);
  const int exit = firstFrame(frames, [&](const Frame& f) { return &f - frames.data() > entry && !f.decision.imu_dominated; });
  ASSERT_GT(exit, entry);
  // The drifting estimate may hold the interval while its speed falls (the braking it saw), not
  // once it has turned: 1.5 m/s downwards is reached 32 frames after the stop.
  EXPECT_LT(exit, stop_frame + 32) << "exit " << exit << ", stop " << stop_frame;
}

TEST(MotionConflictMonitor, AnIntervalReopeningSoonHoldsTheBiasHeldBeforeNotTheBendBeforeIt) {
  // Between a ride's start and its detection the estimator bends its bias. Once an interval that
  // held the biases has closed, the lagged reference must not reach back into that bend: an
  // interval reopening within bias_reference_lag_frames would hold it. (A 40 s vehicle ride of
  // the sweep opened and closed two selective intervals in 2 s; the third held a gyro bias 0.0009
  // rad/s off, and the tilt that grew from it kept the interval open 15 s past the stop.) An
  // IMU-dominated exit restarts the warm-up, so a selective interval shows it: the cabin fills
  // the view, every track is eliminated, and the thin view holds the biases. The lag is 100
  // frames here, so both rides and the stop between them fall inside it.
  constexpr int kLag = 100, kRide1 = 150, kRide2 = 248;
  constexpr int kBendFrames = 25;  // the estimate bends from the ride's start until it is held
  constexpr double kBend = 0.08;   // m/s^2 along x, inside the settling rule's 5 sigma
  Scenario sc = cabin(80, kRide1);
  sc.traj.v0.setZero();  // the cabin stands between its rides
  sc.traj.accel_x = 0;
  sc.traj.brake_start_s = frameSeconds(kRide1 + 20);
  sc.traj.second_pulse_start_s = frameSeconds(kRide2);
  sc.commit_adjust = [=](int k, const MotionConflictMonitor::Decision& d, MotionConflictMonitor::State* s) {
    if (d.hold_bias)
      s->bias = d.held_bias;
    else if (k >= kRide1 && k < kRide1 + kBendFrames)
      s->bias.accel.x() += kBend;
  };
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kSelective);
  o.bias_reference_lag_frames = kLag;
  const auto frames = run(sc, o, kRide2 + 40);
  const int hold1 = firstFrame(frames, [](const Frame& f) { return f.decision.hold_bias; });
  ASSERT_GT(hold1, kRide1);
  ASSERT_LT(hold1, kRide1 + kBendFrames);
  const int exit1 = firstFrame(frames, [&](const Frame& f) { return &f - frames.data() > hold1 && !inConflict(f); });
  ASSERT_GE(exit1, kRide1 + 40) << "closes once the cabin has stopped";
  ASSERT_LT(exit1, kRide2);
  const int hold2 = firstFrame(frames, [&](const Frame& f) { return &f - frames.data() > exit1 && f.decision.hold_bias; });
  ASSERT_GT(hold2, kRide2);
  ASSERT_LT(hold2, exit1 + kLag);
  // Without the rule the reference, lagging 100 frames behind, would come from the bend.
  ASSERT_GE(hold2 - 1 - kLag, kRide1);
  ASSERT_LT(hold2 - 1 - kLag, hold1);
  for (const int k : {hold1, hold2}) {
    EXPECT_FALSE(frames[k].decision.imu_dominated) << "frame " << k;
    EXPECT_LT((frames[k].decision.held_bias.accel - sc.imu_bias.accel).norm(), 1e-12)
        << "frame " << k << " holds " << frames[k].decision.held_bias.accel.transpose();
  }
}

TEST(MotionConflictMonitor, AnIntervalEndingWithAVelocityJumpRestartsAtVisionsVelocity) {
  // The cruising cabin without the hold: the interval ends while the cabin moves at 1.5 m/s with
  // the device at rest inside it. The inertial velocity (the committed true 1.5 m/s) and vision's
  // (at rest in what it sees) differ by the cruise speed.
  Scenario sc = cabin(80, kCabinFrame);
  sc.traj.pulse_peak = 3.0;
  const int frames_total = kCabinFrame + 160;
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kImu);
  o.hold_min_secondary_speed_mps = 1e9;
  const auto frames = run(sc, o, frames_total);
  const int entry = firstFrame(frames, [](const Frame& f) { return f.decision.imu_dominated; });
  ASSERT_GT(entry, kCabinFrame);
  const int exit = firstFrame(frames, [&](const Frame& f) { return &f - frames.data() > entry && !f.decision.imu_dominated; });
  ASSERT_GT(exit, entry);
  // (With the true cruise committed as the solved state the conflict opens again; every interval
  // restarts once, at its end.)
  for (int k = 1; k < frames_total; ++k) {
    const bool exits = frames[k - 1].decision.imu_dominated && !frames[k].decision.imu_dominated;
    EXPECT_EQ(frames[k].decision.restart_on_exit, exits) << "frame " << k;
  }
  const auto& d = frames[exit].decision;
  EXPECT_NEAR(d.exit_velocity_jump_mps, 1.5, 0.1);
  EXPECT_LT(d.exit_state.v.norm(), 0.05) << "vision's velocity: at rest in the cabin";
  EXPECT_LT((d.exit_state.p - sc.traj.position(frameSeconds(exit))).norm(), 0.1);
  EXPECT_LT((d.exit_state.bias.accel - d.held_bias.accel).norm(), 1e-12);
  EXPECT_LT((d.exit_state.bias.gyro - d.held_bias.gyro).norm(), 1e-12);

  // A jump below the threshold is left to the window, and so is every exit with the option off.
  o.restart_min_velocity_jump_mps = 2.0;
  for (const auto& f : run(sc, o, frames_total)) EXPECT_FALSE(f.decision.restart_on_exit);
  o.restart_min_velocity_jump_mps = 0.2;
  o.restart_on_exit = false;
  for (const auto& f : run(sc, o, frames_total)) EXPECT_FALSE(f.decision.restart_on_exit);
}

namespace {

// Tracks that appear in view once the pedestrian's interval is open: 30 static points, and 12 more
// on the walking pedestrian.
constexpr int kLateFrame = kWalkFrame + 8;
constexpr std::uint64_t kLateStaticId = 500, kLatePedestrianId = 2000;

Scenario pedestrianSceneWithLateTracks() {
  Scenario sc = pedestrianScene();
  auto late_static = staticPoints(30, kLateStaticId, 11);
  for (auto& p : late_static) p.appear_s = frameSeconds(kLateFrame);
  const auto late_walker = walkingPedestrian(kLatePedestrianId, 7, kLateFrame);
  sc.points.insert(sc.points.end(), late_static.begin(), late_static.end());
  sc.points.insert(sc.points.end(), late_walker.begin(), late_walker.end());
  return sc;
}

bool isLateStatic(std::uint64_t id) { return id >= kLateStaticId && id < kLateStaticId + 30; }
bool isLatePedestrian(std::uint64_t id) { return id >= kLatePedestrianId; }

}  // namespace

TEST(MotionConflictMonitor, TracksBornInAConflictWaitForAConsistentTest) {
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto frames = run(pedestrianSceneWithLateTracks(), o, kPedestrianFrames);
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GE(entry, kWalkFrame);
  ASSERT_LT(entry, kLateFrame);
  // Tracks seen before the interval are never held out.
  for (const auto& f : frames)
    for (const auto id : f.on_probation) EXPECT_TRUE(isLateStatic(id) || isLatePedestrian(id)) << "track " << id;
  // At first sight every new track waits: none of them has been tested yet.
  int late_seen = 0;
  for (const auto id : frames[kLateFrame].observed) {
    if (!isLateStatic(id) && !isLatePedestrian(id)) continue;
    ++late_seen;
    EXPECT_EQ(frames[kLateFrame].on_probation.count(id), 1u) << "track " << id;
  }
  EXPECT_GT(late_seen, 20);
  // Once the horizon has passed, the static ones have agreed with the IMU and are let in; the
  // walking ones have not (and end up eliminated).
  const Frame& later = frames[kLateFrame + o.horizon_frames + 3];
  ASSERT_TRUE(inConflict(later));
  int static_in = 0, walkers = 0;
  for (const auto id : later.observed) {
    if (isLateStatic(id)) static_in += later.on_probation.count(id) == 0 ? 1 : 0;
    if (isLatePedestrian(id)) ++walkers;
  }
  EXPECT_GT(static_in, 20);
  EXPECT_GT(walkers, 6);
  std::set<std::uint64_t> eliminated;
  for (const auto& f : frames) eliminated.insert(f.decision.eliminate.begin(), f.decision.eliminate.end());
  for (const auto id : later.observed) {
    if (isLatePedestrian(id)) {
      EXPECT_TRUE(later.on_probation.count(id) != 0 || eliminated.count(id) != 0) << "walking track " << id << " let in";
    }
  }
  // After the interval, nothing waits.
  int closed = kLeaveFrame;
  while (closed < kPedestrianFrames && inConflict(frames[closed])) ++closed;
  ASSERT_LT(closed, kPedestrianFrames - 2);
  for (int k = closed + 1; k < kPedestrianFrames; ++k) EXPECT_TRUE(frames[k].on_probation.empty()) << "frame " << k;
}

TEST(MotionConflictMonitor, NoProbationInReferenceModeOrWhenDisabled) {
  conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kReference);
  for (const auto& f : run(pedestrianSceneWithLateTracks(), o, kPedestrianFrames)) EXPECT_TRUE(f.on_probation.empty());
  o = withMode(conflict::ResolutionMode::kAuto);
  o.new_landmark_probation = false;
  for (const auto& f : run(pedestrianSceneWithLateTracks(), o, kPedestrianFrames)) EXPECT_TRUE(f.on_probation.empty());
}

TEST(MotionConflictMonitor, TracksBornTheFrameBeforeTheSuspicionWaitToo) {
  // An occluder's tracks appear one frame before they can disagree with anything; their second
  // observation would pull the pose on the frame that raised the suspicion.
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto isActive = [](const Frame& f) { return f.decision.report.state != ConflictReport::State::kNone; };
  const int first_active = firstFrame(run(pedestrianScene(), o, kPedestrianFrames), isActive);
  ASSERT_GT(first_active, kWalkFrame);
  constexpr std::uint64_t kBornBefore = 700, kBornEarlier = 800;
  Scenario sc = pedestrianScene();
  auto born_before = staticPoints(20, kBornBefore, 21);
  for (auto& p : born_before) p.appear_s = frameSeconds(first_active - 1);
  auto born_earlier = staticPoints(20, kBornEarlier, 22);
  for (auto& p : born_earlier) p.appear_s = frameSeconds(first_active - 2);
  sc.points.insert(sc.points.end(), born_before.begin(), born_before.end());
  sc.points.insert(sc.points.end(), born_earlier.begin(), born_earlier.end());
  const auto frames = run(sc, o, kPedestrianFrames);
  ASSERT_EQ(firstFrame(frames, isActive), first_active) << "the added static tracks moved the onset";
  const Frame& f = frames[static_cast<std::size_t>(first_active)];
  int before = 0, earlier = 0;
  for (const auto id : f.observed) {
    if (id >= kBornBefore && id < kBornBefore + 20) {
      ++before;
      EXPECT_EQ(f.on_probation.count(id), 1u) << "track " << id << " born the frame before";
    }
    if (id >= kBornEarlier && id < kBornEarlier + 20) {
      ++earlier;
      EXPECT_EQ(f.on_probation.count(id), 0u) << "track " << id << " born two frames before";
    }
  }
  EXPECT_GT(before, 10);
  EXPECT_GT(earlier, 10);
}

// A slow object's drift over the horizon is about what the reference state's attitude uncertainty
// spreads every predicted pixel by (through gravity): at the propagated test's 10 mrad its tracks
// pass the landmark test, at the landmark test's own 4 mrad they fail it; every track passes both
// before it moves. The region split is off, so only the IMU-referenced tests judge.
TEST(MotionConflictMonitor, TheLandmarkTestsOwnAttitudeSigmaFindsASlowObject) {
  const double speed = 0.1;  // 5 cm over the horizon, 3 px at 7 m
  auto runWith = [&](double landmark_attitude_sigma) {
    conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kReference);
    o.split_chi2_threshold = 0;
    o.observation_sigma_px = 0.4;  // the shipped pipeline's
    o.landmark_attitude_sigma_rad = landmark_attitude_sigma;
    return run(slowObjectScene(speed), o, kDriftFrames);
  };
  const auto shared = runWith(0.0);  // 0: the propagated test's attitude_sigma_rad (10 mrad)
  const auto own = runWith(0.004);
  for (int k = 0; k < kDriftFrames; ++k) {
    EXPECT_EQ(shared[k].decision.report.landmarks_inconsistent, 0) << "frame " << k;
    if (k < kDriftFrame) {
      EXPECT_EQ(own[k].decision.report.landmarks_inconsistent, 0) << "frame " << k;
    }
  }
  // Of the object's 60 tracks (80 static beside them).
  EXPECT_GE(own.back().decision.report.landmarks_inconsistent, 30);
  EXPECT_LE(own.back().decision.report.landmarks_inconsistent, 60);
}

// A carried object (40 tracks 1-1.5 m ahead and to the sides, fixed to the device) opens a selective interval
// beside 70 static points. Four seconds later all but 10 of those leave the view: vision as a
// whole disagrees and too few static landmarks are left, so auto goes IMU-dominated. The
// selective estimate up to there was good; the rewind goes back only from where vision as a whole
// began to disagree, not to before the interval's start (which by then has left the history, so
// the rewind went to its oldest frame, 5.6 s back on a rendered self-occlusion: 0.112 m instead of
// 0.015 m).
TEST(MotionConflictMonitor, ALateSwitchToImuDominatedRewindsOnlyOverTheWholeViewEvidence) {
  constexpr int kCarryFrame = 100, kThinFrame = 180, kFrames = 200;
  Scenario sc;
  sc.points = staticPoints(70, 0, 23);
  for (int i = 10; i < 70; ++i) sc.points[static_cast<std::size_t>(i)].leave_s = frameSeconds(kThinFrame);
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double attach = frameSeconds(kCarryFrame);
  for (int i = 0; i < 40; ++i) {
    Point p;
    p.id = 1000 + static_cast<std::uint64_t>(i);
    // Off the axis the device moves along, where its own motion shows in the image.
    const double side = i % 2 == 0 ? 1.0 : -1.0;
    p.X_W = sc.traj.position(attach) + Eigen::Vector3d(1.25 + 0.25 * u(rng), side * (0.6 + 0.3 * u(rng)), 0.5 * u(rng));
    p.attach_s = attach;
    p.appear_s = attach;
    sc.points.push_back(p);
  }
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  const auto frames = run(sc, o, kFrames);
  const int entry = firstFrame(frames, inConflict);
  ASSERT_GE(entry, kCarryFrame);
  ASSERT_LE(entry, kCarryFrame + o.horizon_frames + o.enter_frames);  // new tracks wait a horizon
  for (int k = entry; k < kThinFrame; ++k) {
    ASSERT_TRUE(inConflict(frames[k])) << "frame " << k;
    ASSERT_FALSE(frames[k].decision.imu_dominated) << "selective beside 70 static points, frame " << k;
  }
  const int imu = firstFrame(frames, [](const Frame& f) { return f.decision.imu_dominated; });
  ASSERT_GE(imu, kThinFrame);
  ASSERT_LE(imu, kThinFrame + o.enter_frames + 1);
  for (int k = entry; k <= imu; ++k) EXPECT_EQ(frames[k].decision.report.interval_start, frames[entry].decision.report.interval_start);
  const auto& d = frames[imu].decision;
  ASSERT_TRUE(d.rewind);
  EXPECT_GE(d.rewind_t, frameTime(kThinFrame - o.horizon_frames)) << "rewound over the selective estimate";
  EXPECT_LT(d.rewind_t, frameTime(imu));
  // The rewound state, propagated over the exact IMU, is this frame's.
  EXPECT_LT((d.rewind_state.p - sc.traj.position(frameSeconds(imu))).norm(), 1e-3);
}

// frontend_evidence_after_imu_exit: the warm-up after an IMU-dominated interval waits out the
// velocity the interval drifted, which the frontend's labels do not use. A group the frontend
// labels 5 frames after the stopped cabin's interval closed (an occluder carried into view) opens
// a selective interval at once; with the option off it waits the whole warm-up.
TEST(MotionConflictMonitor, FrontendLabelsNeedNoWarmUpAfterAnImuDominatedInterval) {
  Scenario sc = stoppingCabin();
  sc.frontend_labels = true;
  const int frames_total = kStopFrame + 100;
  const conflict::ConflictOptions o = withMode(conflict::ResolutionMode::kAuto);
  ASSERT_TRUE(o.frontend_evidence_after_imu_exit) << "the default";
  const auto unlabelled = run(sc, o, frames_total);
  const int imu = firstFrame(unlabelled, [](const Frame& f) { return f.decision.imu_dominated; });
  ASSERT_GT(imu, kCabinFrame);
  const int exit = firstFrame(unlabelled, [&](const Frame& f) { return &f - unlabelled.data() > imu && !inConflict(f); });
  ASSERT_GE(exit, kStopFrame);
  const int warm = exit + o.warmup_frames;  // the first frame after the warm-up
  ASSERT_LT(warm, frames_total);
  for (int k = exit; k < warm; ++k) ASSERT_FALSE(inConflict(unlabelled[k])) << "frame " << k;

  const int labelled_from = exit + 5;
  for (std::size_t i = 0; i < 20; ++i) {
    sc.points[i].frontend_inconsistent = true;
    sc.points[i].frontend_inconsistent_from_s = frameSeconds(labelled_from);
  }
  const auto on = run(sc, o, frames_total);
  for (int k = 0; k < labelled_from; ++k)
    ASSERT_EQ(on[k].decision.report.state, unlabelled[k].decision.report.state) << "frame " << k;
  const int entry = firstFrame(on, [&](const Frame& f) { return &f - on.data() >= exit && inConflict(f); });
  EXPECT_EQ(entry, labelled_from + o.enter_frames - 1);
  ASSERT_GE(entry, 0);
  for (int k = entry; k < warm; ++k) {
    EXPECT_TRUE(inConflict(on[k])) << "frame " << k;
    EXPECT_FALSE(on[k].decision.imu_dominated) << "a labelled group beside static tracks, frame " << k;
  }

  conflict::ConflictOptions off = o;
  off.frontend_evidence_after_imu_exit = false;
  const auto waited = run(sc, off, frames_total);
  const int late = firstFrame(waited, [&](const Frame& f) { return &f - waited.data() >= exit && inConflict(f); });
  EXPECT_GE(late, warm) << "the whole warm-up";
}
