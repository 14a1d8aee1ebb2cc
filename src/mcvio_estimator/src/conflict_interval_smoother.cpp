#include "mcvio/estimator/conflict_interval_smoother.hpp"

#include <sstream>

#include <Eigen/Dense>

#include "mcvio/estimator/imu_preintegrator.hpp"
#include "mcvio/estimator/so3.hpp"

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

void ConflictIntervalSmoother::addFrame(Timestamp t, const Eigen::Quaterniond& q) {
  if (!active_ || t <= (frames_.empty() ? t0_ : frames_.back().t)) return;
  if (toSeconds(t - t0_) > options_.max_window_s) {
    active_ = false;
    frames_.clear();
    return;
  }
  frames_.push_back({t, q.normalized()});
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
                                                                  const std::vector<SettledVelocity>& settled,
                                                                  const ReidentifiedEnd* reidentified,
                                                                  const StartCovariance* start) {
  Result res;
  active_ = false;
  if (frames_.empty()) {
    res.message = "no frames in the conflict window";
    return res;
  }
  // Inertial propagation over the window, and the Jacobians of velocity and position with respect
  // to one acceleration correction in the world frame, scaled over time by its expected growth:
  // shape(tau) = (sigma0^2 + q (tau - tau^2 / 2T)) / (sigma0^2 + q T / 2), 1 at the end T.
  // Columns 3-8: a constant and a ramp tau / T, the two terms fitted with a re-identified end.
  const double window_s = toSeconds(frames_.back().t - t0_);
  const double sigma0_sq = options_.held_acceleration_sigma * options_.held_acceleration_sigma;
  const double q = noise.accelerometer_random_walk * noise.accelerometer_random_walk;
  const auto shape = [&](double tau) {
    return (sigma0_sq + q * (tau - tau * tau / (2.0 * window_s))) / (sigma0_sq + q * window_s / 2.0);
  };
  using Jacobian = Eigen::Matrix<double, 3, 9>;
  Eigen::Vector3d p = p0_, v = v0_;
  Jacobian Jp = Jacobian::Zero(), Jv = Jacobian::Zero();
  Eigen::Matrix3d R = q0_.toRotationMatrix();
  Timestamp t = t0_;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Jacobian> jacobians;
  positions.reserve(frames_.size());
  jacobians.reserve(frames_.size());
  std::vector<ImuSample> samples;
  std::vector<std::pair<Jacobian, Eigen::Vector3d>> velocity_rows;  // Jv and the velocity error
  ErrorCovariance P = ErrorCovariance::Zero();
  if (start != nullptr) {
    const int at[4] = {0, 3, 9, 12};  // attitude, velocity, gyro bias, accel bias
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) P.block<3, 3>(at[a], at[b]) = start->block<3, 3>(3 * a, 3 * b);
  }
  for (const auto& f : frames_) {
    if (!imu.extract(t, f.t, &samples) || samples.size() < 2) {
      std::ostringstream os;
      os << "no IMU between " << t << " and " << f.t << " ns in the conflict window";
      res.message = os.str();
      return res;
    }
    ImuPreintegrator pre(bias_, noise);
    for (const auto& s : samples) pre.integrate(s);
    const double dt = pre.deltaTime();
    const double tau = toSeconds(t - t0_) + 0.5 * dt;
    const Eigen::Vector3d g(shape(tau), 1.0, window_s > 0 ? tau / window_s : 0.0);
    p += v * dt + 0.5 * gravity * dt * dt + R * pre.deltaP();
    for (int k = 0; k < 3; ++k) {
      Jp.block<3, 3>(0, 3 * k) += Jv.block<3, 3>(0, 3 * k) * dt + 0.5 * dt * dt * g[k] * Eigen::Matrix3d::Identity();
      Jv.block<3, 3>(0, 3 * k) += dt * g[k] * Eigen::Matrix3d::Identity();
    }
    v += gravity * dt + R * pre.deltaV();
    positions.push_back(p);
    jacobians.push_back(Jp);
    if (start != nullptr) propagateError(R, pre, &P);
    for (const auto& sv : settled)
      if (sv.t == f.t) {
        velocity_rows.emplace_back(Jv, sv.v - v);
        if (start != nullptr) accumulateSettledError(Jv, &P);
      }
    R = f.q.toRotationMatrix();
    t = f.t;
  }
  // The correction that makes the inertial velocities after the exit the visual ones.
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const auto& [J, e] : velocity_rows) {
    normal += J.leftCols<3>().transpose() * J.leftCols<3>();
    rhs += J.leftCols<3>().transpose() * e;
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(normal);
  if (velocity_rows.empty() || !lu.isInvertible()) {
    res.message = "no settled velocity to fit the conflict window to";
    return res;
  }
  Eigen::Matrix<double, 9, 1> c = Eigen::Matrix<double, 9, 1>::Zero();
  c.head<3>() = lu.solve(rhs);
  Eigen::Matrix<double, 6, 6> A6_inverse = Eigen::Matrix<double, 6, 6>::Zero();  // with a re-identified end
  double largest = c.head<3>().norm();
  std::ostringstream note;
  if (reidentified != nullptr) {
    // Would a held bias error explain where vision puts the end? sigma0 T^2 / 2 per axis.
    const Eigen::Vector3d miss = reidentified->p - (positions.back() + jacobians.back() * c);
    const double gate = 3.0 * (0.5 * options_.held_acceleration_sigma * window_s * window_s + reidentified->sigma);
    if (miss.norm() > gate) {
      note << "; the end position from " << reidentified->landmarks << " re-identified landmarks is " << miss.norm()
           << " m off (more than " << gate << " m), not used";
    } else {
      // Constant and ramp against the settled velocities and the end position, each row weighed
      // by its sigma.
      Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
      const double wv = 1.0 / (options_.settled_velocity_sigma * options_.settled_velocity_sigma);
      for (const auto& [J, e] : velocity_rows) {
        A += wv * J.rightCols<6>().transpose() * J.rightCols<6>();
        b += wv * J.rightCols<6>().transpose() * e;
      }
      const double wp = 1.0 / (reidentified->sigma * reidentified->sigma);
      const auto Jend = jacobians.back().rightCols<6>();
      A += wp * Jend.transpose() * Jend;
      b += wp * Jend.transpose() * (reidentified->p - positions.back());
      const Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu6(A);
      const Eigen::Matrix<double, 6, 1> c6 = lu6.solve(b);
      // The correction at its largest: a constant plus a ramp peaks at one end of the window.
      const double largest6 = std::max(c6.head<3>().norm(), (c6.head<3>() + c6.tail<3>()).norm());
      if (lu6.isInvertible() && c6.allFinite() && largest6 <= options_.max_acceleration_correction) {
        c.setZero();
        c.tail<6>() = c6;
        A6_inverse = lu6.inverse();
        largest = largest6;
        res.used_reidentified = true;
        note << "; end position from " << reidentified->landmarks << " re-identified landmarks ("
             << miss.norm() << " m from the velocity fit)";
      } else {
        note << "; the end position from " << reidentified->landmarks << " re-identified landmarks needs "
             << largest6 << " m/s^2, not used";
      }
    }
  }
  if (!c.allFinite() || largest > options_.max_acceleration_correction) {
    std::ostringstream os;
    os << "acceleration correction of " << largest << " m/s^2 exceeds smoothing_max_acceleration_correction "
       << options_.max_acceleration_correction << " (the end velocity is not the world's); window left as estimated";
    res.message = os.str();
    return res;
  }
  res.revisions.reserve(frames_.size());
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    const Node& n = frames_[i];
    const Eigen::Vector3d p_revised = positions[i] + jacobians[i] * c;
    res.revisions.push_back({n.t, p_revised, n.q});
    if (n.has_secondary) res.secondary_revisions.push_back({n.t, n.p_WS + (p_revised - n.p_WB), n.q_WS});
  }
  res.acceleration_correction = c.head<3>() + c.segment<3>(3) + c.segment<3>(6);
  res.shift = res.revisions.back().p_WB - p_end;
  res.applied = res.shift.allFinite();
  if (start != nullptr) {
    // The corrected end's error is linear in the propagated errors (the end position, the settled
    // velocities' sum) and in the measurements' own: r = C x + D n_v (+ D_p n_p). A settled
    // velocity's error is taken as common to all of them (they come from one estimator).
    Eigen::Matrix<double, 9, 3> S = Eigen::Matrix<double, 9, 3>::Zero();
    for (const auto& row : velocity_rows) S += row.first.transpose();
    Eigen::Matrix<double, 3, 24> C = Eigen::Matrix<double, 3, 24>::Zero();
    Eigen::Matrix3d D, Dp = Eigen::Matrix3d::Zero();
    const double sv = options_.settled_velocity_sigma;
    if (!res.used_reidentified) {
      const Eigen::Matrix3d K = jacobians.back().leftCols<3>() * lu.inverse();
      C.block<3, 3>(0, 6).setIdentity();
      C.block<3, 3>(0, 15) = -K;
      D = K * S.topRows<3>();
    } else {
      const double wv = 1.0 / (sv * sv), wp = 1.0 / (reidentified->sigma * reidentified->sigma);
      const Eigen::Matrix<double, 3, 6> Jend = jacobians.back().rightCols<6>();
      const Eigen::Matrix<double, 3, 6> K = Jend * A6_inverse;
      C.block<3, 3>(0, 6) = Eigen::Matrix3d::Identity() - wp * K * Jend.transpose();
      C.block<3, 6>(0, 18) = -wv * K;
      D = wv * K * S.bottomRows<6>();
      Dp = wp * K * Jend.transpose() * reidentified->sigma;
    }
    res.shift_covariance = C * P * C.transpose() + sv * sv * D * D.transpose() + Dp * Dp.transpose();
    res.shift_covariance = 0.5 * (res.shift_covariance + res.shift_covariance.transpose()).eval();
    res.shift_covariance_valid = res.shift_covariance.allFinite();
  }
  std::ostringstream os;
  os << "conflict window of " << window_s << " s smoothed: acceleration correction " << largest
     << " m/s^2, end position moved " << res.shift.norm() << " m";
  if (res.shift_covariance_valid) {
    const Eigen::Vector3d sigma = res.shift_covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
    os << " (sigma " << sigma.x() << " / " << sigma.y() << " / " << sigma.z() << " m)";
  }
  os << note.str();
  res.message = os.str();
  return res;
}

void ConflictIntervalSmoother::propagateError(const Eigen::Matrix3d& R, const ImuPreintegrator& pre,
                                              ErrorCovariance* P) {
  // Errors are estimate minus truth. The rotated increments carry the attitude error into the
  // velocity and position, the bias Jacobians the held biases' error, the preintegration's
  // covariance the IMU's noise (its attitude at the segment's end, its velocity and position in
  // the body frame at its start).
  const double dt = pre.deltaTime();
  const Eigen::Matrix3d R_end = R * pre.deltaQ().toRotationMatrix();
  ErrorCovariance F = ErrorCovariance::Identity();
  F.block<3, 3>(0, 9) = R_end * pre.dR_dbg();
  F.block<3, 3>(3, 0) = -so3::hat(R * pre.deltaV());
  F.block<3, 3>(3, 9) = R * pre.dV_dbg();
  F.block<3, 3>(3, 12) = R * pre.dV_dba();
  F.block<3, 3>(6, 0) = -so3::hat(R * pre.deltaP());
  F.block<3, 3>(6, 3) = dt * Eigen::Matrix3d::Identity();
  F.block<3, 3>(6, 9) = R * pre.dP_dbg();
  F.block<3, 3>(6, 12) = R * pre.dP_dba();
  ImuPreintegrator::Matrix15 T = ImuPreintegrator::Matrix15::Identity();
  T.block<3, 3>(0, 0) = R_end;
  T.block<3, 3>(3, 3) = R;
  T.block<3, 3>(6, 6) = R;
  *P = F * *P * F.transpose();
  P->topLeftCorner<15, 15>() += T * pre.covariance() * T.transpose();
}

void ConflictIntervalSmoother::accumulateSettledError(const Eigen::Matrix<double, 3, 9>& Jv, ErrorCovariance* P) {
  ErrorCovariance A = ErrorCovariance::Identity();
  A.block<9, 3>(15, 3) = Jv.transpose();
  *P = A * *P * A.transpose();
}

}  // namespace mcvio::estimator
