#include "mcvio/estimator/conflict_interval_smoother.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Dense>

#include "mcvio/estimator/imu_preintegrator.hpp"

namespace mcvio::estimator {

void ConflictIntervalSmoother::begin(Timestamp t0, const Eigen::Vector3d& p0, const Eigen::Quaterniond& q0,
                                     const Eigen::Vector3d& v0, const ImuBias& bias) {
  active_ = true;
  exited_ = false;
  t0_ = t0;
  p0_ = p0;
  q0_ = q0.normalized();
  v0_ = v0;
  bias_ = bias;
  frames_.clear();
  exit_index_ = 0;
}

void ConflictIntervalSmoother::addFrame(Timestamp t, const Eigen::Quaterniond& q, bool rewound) {
  if (!active_ || t <= (frames_.empty() ? t0_ : frames_.back().t)) return;
  if (toSeconds(t - t0_) > options_.max_window_s) {
    active_ = false;
    frames_.clear();
    return;
  }
  Node n;
  n.t = t;
  n.q = q.normalized();
  n.rewound = rewound;
  frames_.push_back(n);
}

void ConflictIntervalSmoother::setSecondary(Timestamp t, const Eigen::Vector3d& p_WB, const Eigen::Vector3d& p_WS,
                                            const Eigen::Quaterniond& q_WS) {
  if (!active_ || frames_.empty() || frames_.back().t != t) return;
  Node& n = frames_.back();
  n.has_secondary = true;
  n.p_WB = p_WB;
  n.p_WS = p_WS;
  n.q_WS = q_WS.normalized();
}

void ConflictIntervalSmoother::markExit() {
  if (!active_) return;
  exited_ = true;
  exit_index_ = frames_.size();
}

bool ConflictIntervalSmoother::ready() const {
  return exited() && frames_.size() >= exit_index_ + static_cast<std::size_t>(options_.settle_frames);
}

ConflictIntervalSmoother::Result ConflictIntervalSmoother::finish(const ImuBuffer& imu, const ImuNoiseParams& noise,
                                                                  const Eigen::Vector3d& gravity,
                                                                  const Eigen::Vector3d& p_end,
                                                                  const std::vector<SettledVelocity>& settled) {
  Result res;
  active_ = false;
  if (frames_.empty()) {
    res.message = "no frames in the conflict window";
    return res;
  }
  // Inertial propagation over the window with the held biases. Each step keeps its duration and
  // the attitude it used: the error model below needs both.
  struct Step {
    double dt = 0;
    double mid_s = 0;  ///< its middle, from the start of the window [s]
    Eigen::Matrix3d R;
  };
  struct Observation {
    std::size_t step = 0;   ///< the velocity after this step
    Eigen::Vector3d error;  ///< settled (visual) minus inertial velocity
  };
  std::vector<Step> steps;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Observation> observations;
  steps.reserve(frames_.size());
  positions.reserve(frames_.size());
  Eigen::Vector3d p = p0_, v = v0_;
  Eigen::Matrix3d R = q0_.toRotationMatrix();
  Timestamp t = t0_;
  double elapsed = 0;
  std::vector<ImuSample> samples;
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const Node& f = frames_[k];
    if (!imu.extract(t, f.t, &samples) || samples.size() < 2) {
      std::ostringstream os;
      os << "no IMU between " << t << " and " << f.t << " ns in the conflict window";
      res.message = os.str();
      return res;
    }
    ImuPreintegrator pre(bias_, noise);
    for (const auto& s : samples) pre.integrate(s);
    const double dt = pre.deltaTime();
    steps.push_back({dt, elapsed + 0.5 * dt, R});
    elapsed += dt;
    p += v * dt + 0.5 * gravity * dt * dt + R * pre.deltaP();
    v += gravity * dt + R * pre.deltaV();
    positions.push_back(p);
    for (const auto& sv : settled)
      if (sv.t == f.t) observations.push_back({k, sv.v - v});
    // A rewound frame's attitude was estimated while the conflict pulled it: integrate the gyro
    // over it, as the estimator's rewind does.
    R = f.rewound ? Eigen::Matrix3d(R * pre.deltaQ().toRotationMatrix()) : f.q.toRotationMatrix();
    t = f.t;
  }
  if (observations.empty()) {
    res.message = "no settled velocity to fit the conflict window to";
    return res;
  }

  // The acceleration error of step j, a linear function of standard normals z:
  //   e_j = P (s_t n_t + s_r tau_j n_r) + R_j (s_b n_b + sum_{i<=j} sqrt(q dt_i) n_i)
  // with P the horizontal projection (a tilt error leaks gravity sideways; it starts s_t off and
  // grows at s_r per second as the held gyro bias turns the attitude), the held accelerometer
  // bias's error s_b in the body frame, and the random walk of the true bias since (q). Each
  // settled velocity error is linear in z (the rows of H); the corrections are the conditional
  // mean given them, E[z | y] = H^T (H H^T + sigma_y^2 I)^-1 y.
  const std::size_t n = steps.size(), m = observations.size();
  const double st = options_.tilt_acceleration_sigma, sr = options_.tilt_acceleration_rate_sigma;
  const double sb = options_.held_acceleration_sigma;
  const double q = noise.accelerometer_random_walk * noise.accelerometer_random_walk;
  // The settled velocities come from one estimator a few frames apart: together they are worth
  // one measurement of velocity_sigma, not m independent ones.
  const double sy = options_.velocity_sigma * std::sqrt(static_cast<double>(m));
  const Eigen::Matrix3d P = Eigen::Vector3d(1, 1, 0).asDiagonal();
  std::vector<Eigen::Matrix3d> rotated(n + 1, Eigen::Matrix3d::Zero());  // sum of dt_j R_j over j < k
  std::vector<double> time(n + 1, 0.0), ramp(n + 1, 0.0);                  // sums of dt_j, dt_j tau_j
  for (std::size_t j = 0; j < n; ++j) {
    rotated[j + 1] = rotated[j] + steps[j].dt * steps[j].R;
    time[j + 1] = time[j] + steps[j].dt;
    ramp[j + 1] = ramp[j] + steps[j].dt * steps[j].mid_s;
  }
  constexpr Eigen::Index kFixed = 9;  // n_t, n_r, n_b; then one walk increment per step
  const auto walkColumn = [](std::size_t i) { return kFixed + static_cast<Eigen::Index>(3 * i); };
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(3 * m), walkColumn(n));
  Eigen::VectorXd y(static_cast<Eigen::Index>(3 * m));
  for (std::size_t r = 0; r < m; ++r) {
    const std::size_t end = observations[r].step + 1;  // the velocity integrates steps 0 .. step
    const auto row = static_cast<Eigen::Index>(3 * r);
    y.segment<3>(row) = observations[r].error;
    H.block<3, 3>(row, 0) = st * time[end] * P;
    H.block<3, 3>(row, 3) = sr * ramp[end] * P;
    H.block<3, 3>(row, 6) = sb * rotated[end];
    for (std::size_t i = 0; i < end; ++i)
      H.block<3, 3>(row, walkColumn(i)) = std::sqrt(q * steps[i].dt) * (rotated[end] - rotated[i]);
  }
  Eigen::MatrixXd S = H * H.transpose();
  S.diagonal().array() += sy * sy;
  // Positive definite in exact arithmetic; a prior far wider than velocity_sigma leaves it
  // numerically rank-deficient, where the least-squares solution is the limit wanted.
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
  const Eigen::VectorXd z = H.transpose() * (ldlt.info() == Eigen::Success && ldlt.isPositive()
                                                 ? Eigen::VectorXd(ldlt.solve(y))
                                                 : Eigen::VectorXd(S.completeOrthogonalDecomposition().solve(y)));
  if (!z.allFinite()) {
    res.message = "the conflict window's error model could not be solved";
    return res;
  }

  // The corrected accelerations, integrated into position corrections frame by frame.
  const Eigen::Vector3d tilt = st * P * z.segment<3>(0), tilt_rate = sr * P * z.segment<3>(3);
  const Eigen::Vector3d held = sb * z.segment<3>(6);
  Eigen::Vector3d walk = Eigen::Vector3d::Zero(), dv = Eigen::Vector3d::Zero(), dp = Eigen::Vector3d::Zero();
  Eigen::Vector3d correction = Eigen::Vector3d::Zero();
  double largest = 0;
  res.revisions.reserve(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Step& s = steps[j];
    walk += std::sqrt(q * s.dt) * z.segment<3>(walkColumn(j));
    correction = tilt + s.mid_s * tilt_rate + s.R * (held + walk);
    largest = std::max(largest, correction.norm());
    dp += dv * s.dt + 0.5 * s.dt * s.dt * correction;
    dv += s.dt * correction;
    const Node& f = frames_[j];
    const Eigen::Vector3d p_revised = positions[j] + dp;
    res.revisions.push_back({f.t, p_revised, f.q});
    if (f.has_secondary) res.secondary_revisions.push_back({f.t, f.p_WS + (p_revised - f.p_WB), f.q_WS});
  }
  if (!(largest <= options_.max_acceleration_correction)) {
    std::ostringstream os;
    os << "acceleration correction of " << largest << " m/s^2 exceeds smoothing_max_acceleration_correction "
       << options_.max_acceleration_correction << " (the end velocity is not the world's); window left as estimated";
    res = Result{};
    res.message = os.str();
    return res;
  }
  res.acceleration_correction = correction;
  res.shift = res.revisions.back().p_WB - p_end;
  res.applied = res.shift.allFinite();
  std::ostringstream os;
  os << "conflict window of " << toSeconds(frames_.back().t - t0_) << " s smoothed: acceleration correction up to "
     << largest << " m/s^2, end position moved " << res.shift.norm() << " m";
  res.message = os.str();
  return res;
}

}  // namespace mcvio::estimator
