#include "mcvio/sim/sinusoid_trajectory.hpp"

#include <cmath>
#include <stdexcept>

namespace mcvio::sim {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

struct Signal {
  double value = 0, rate = 0, accel = 0;
};

Signal evaluateTerms(const std::vector<SinusoidTerm>& terms, double t) {
  Signal s;
  for (const auto& term : terms) {
    const double w = kTwoPi * term.frequency_hz;
    const double arg = w * t + term.phase;
    const double sn = std::sin(arg), cs = std::cos(arg);
    s.value += term.amplitude * sn;
    s.rate += term.amplitude * w * cs;
    s.accel -= term.amplitude * w * w * sn;
  }
  return s;
}

double sumAbs(const std::vector<SinusoidTerm>& terms) {
  double s = 0;
  for (const auto& term : terms) s += std::abs(term.amplitude);
  return s;
}

}  // namespace

Eigen::Matrix3d lookFromBodyRotation() {
  // Columns: body x (image up) -> look z, body y (image right) -> -look y, body z (optical axis)
  // -> look x.
  Eigen::Matrix3d r;
  r << 0, 0, 1,  //
      0, -1, 0,  //
      1, 0, 0;
  return r;
}

SinusoidTrajectory::Options SinusoidTrajectory::Options::loop(const Eigen::Vector3d& center,
                                                              const Eigen::Vector3d& half,
                                                              double period_s,
                                                              double look_outward) {
  Options o;
  o.center = center;
  const double f = 1.0 / period_s;
  // 85% of the excursion on the main ellipse, the rest on slower and faster wobbles.
  o.x = {{0.80 * half.x(), f, M_PI / 2}, {0.12 * half.x(), 2.3 * f, 0.4},
         {0.03 * half.x(), 0.9, 1.3}, {0.05 * half.x(), 0.37 * f, 2.0}};
  o.y = {{0.80 * half.y(), f, 0.0}, {0.12 * half.y(), 3.1 * f, 1.1},
         {0.03 * half.y(), 1.1, 0.2}, {0.05 * half.y(), 0.53 * f, 0.7}};
  o.z = {{0.60 * half.z(), 1.9 * f, 0.3}, {0.30 * half.z(), 4.3 * f, 2.2},
         {0.10 * half.z(), 0.7, 0.5}};
  // Tangent of the ellipse at t = 0 points along +y; look slightly outward.
  o.yaw0 = M_PI / 2 - look_outward;
  o.yaw_rate = 2.0 * M_PI * f;
  o.yaw = {{0.25, 0.11, 0.0}, {0.03, 0.8, 1.0}};
  o.pitch = {{0.10, 0.07, 0.5}, {0.02, 1.3, 0.0}};
  o.roll = {{0.08, 0.09, 1.5}, {0.02, 1.1, 0.3}};
  return o;
}

SinusoidTrajectory::Options SinusoidTrajectory::Options::handHeld(const Eigen::Vector3d& center,
                                                                  const Eigen::Vector3d& half,
                                                                  double yaw_rate) {
  Options o;
  o.center = center;
  o.x = {{0.6 * half.x(), 0.05, 0.0}, {0.3 * half.x(), 0.17, 1.0}, {0.1 * half.x(), 0.9, 0.2}};
  o.y = {{0.6 * half.y(), 0.04, 1.3}, {0.3 * half.y(), 0.21, 0.1}, {0.1 * half.y(), 1.1, 2.0}};
  o.z = {{0.6 * half.z(), 0.06, 0.7}, {0.3 * half.z(), 0.23, 2.5}, {0.1 * half.z(), 1.3, 0.9}};
  o.yaw0 = 0.0;
  o.yaw_rate = yaw_rate;
  o.yaw = {{0.5, 0.05, 0.0}, {0.1, 0.3, 1.0}, {0.02, 1.2, 0.4}};
  o.pitch = {{0.12, 0.07, 0.5}, {0.03, 0.9, 0.0}};
  o.roll = {{0.10, 0.08, 1.5}, {0.03, 1.0, 0.3}};
  return o;
}

SinusoidTrajectory::SinusoidTrajectory(Options options, Timestamp start, Timestamp end)
    : options_(std::move(options)), start_(start), end_(end) {
  if (end_ <= start_) throw std::invalid_argument("SinusoidTrajectory: end time before start time");
}

Eigen::Vector3d SinusoidTrajectory::maxExcursion() const {
  return {sumAbs(options_.x), sumAbs(options_.y), sumAbs(options_.z)};
}

KinematicState SinusoidTrajectory::evaluate(Timestamp t) const {
  const double s = toSeconds(t - start_);
  const Signal x = evaluateTerms(options_.x, s);
  const Signal y = evaluateTerms(options_.y, s);
  const Signal z = evaluateTerms(options_.z, s);
  Signal yaw = evaluateTerms(options_.yaw, s);
  yaw.value += options_.yaw0 + options_.yaw_rate * s;
  yaw.rate += options_.yaw_rate;
  const Signal pitch = evaluateTerms(options_.pitch, s);
  const Signal roll = evaluateTerms(options_.roll, s);

  KinematicState st;
  st.p_wb = options_.center + Eigen::Vector3d(x.value, y.value, z.value);
  st.v_w = {x.rate, y.rate, z.rate};
  st.a_w = {x.accel, y.accel, z.accel};

  const Eigen::Matrix3d r_wl =
      (Eigen::AngleAxisd(yaw.value, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(pitch.value, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll.value, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Matrix3d r_lb = lookFromBodyRotation();
  st.q_wb = Eigen::Quaterniond(r_wl * r_lb).normalized();

  // Body rates of a z-y-x Euler sequence, expressed in the rotated look frame.
  const double sp = std::sin(pitch.value), cp = std::cos(pitch.value);
  const double sr = std::sin(roll.value), cr = std::cos(roll.value);
  const Eigen::Vector3d omega_l(roll.rate - yaw.rate * sp,
                                pitch.rate * cr + yaw.rate * cp * sr,
                                -pitch.rate * sr + yaw.rate * cp * cr);
  st.omega_b = r_lb.transpose() * omega_l;
  return st;
}

}  // namespace mcvio::sim
