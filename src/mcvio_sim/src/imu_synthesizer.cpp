#include "mcvio/sim/imu_synthesizer.hpp"

#include <cmath>
#include <random>
#include <stdexcept>

namespace mcvio::sim {

ImuSynthesizer::ImuSynthesizer(Options options) : options_(std::move(options)) {
  if (!(options_.noise.rate_hz > 0))
    throw std::invalid_argument("ImuSynthesizer: imu rate_hz must be positive");
}

ImuSample ImuSynthesizer::idealMeasurement(const KinematicState& state, Timestamp t) {
  ImuSample m;
  m.t = t;
  m.gyro = state.omega_b;
  m.accel = state.q_wb.conjugate() * (state.a_w - kGravityW);
  return m;
}

ImuSequence ImuSynthesizer::synthesize(const Trajectory& trajectory, Timestamp start,
                                       Timestamp end) const {
  const ImuNoiseParams& n = options_.noise;
  const Timestamp step = fromSeconds(1.0 / n.rate_hz);
  const double dt = toSeconds(step);
  std::mt19937_64 rng(options_.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto gaussian3 = [&] { return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)); };

  const double sg = n.gyroscope_noise_density / std::sqrt(dt);
  const double sa = n.accelerometer_noise_density / std::sqrt(dt);
  const double sbg = n.gyroscope_random_walk * std::sqrt(dt);
  const double sba = n.accelerometer_random_walk * std::sqrt(dt);

  ImuSequence out;
  const size_t count = static_cast<size_t>((end - start) / step) + 1;
  out.samples.reserve(count);
  out.ground_truth.reserve(count);
  Eigen::Vector3d bg = options_.initial_gyro_bias;
  Eigen::Vector3d ba = options_.initial_accel_bias;
  for (size_t k = 0; k < count; ++k) {
    const Timestamp t = start + static_cast<Timestamp>(k) * step;
    const KinematicState s = trajectory.evaluate(t);
    ImuSample m = idealMeasurement(s, t);
    dataset::GroundTruthState gt;
    gt.t = t;
    gt.p_WB = s.p_wb;
    gt.q_WB = s.q_wb;
    gt.v_WB = s.v_w;
    gt.bias_gyro = bg;
    gt.bias_accel = ba;
    m.gyro += bg;
    m.accel += ba;
    if (options_.add_noise) {
      m.gyro += sg * gaussian3();
      m.accel += sa * gaussian3();
      bg += sbg * gaussian3();
      ba += sba * gaussian3();
    }
    out.samples.push_back(m);
    out.ground_truth.push_back(gt);
  }
  return out;
}

}  // namespace mcvio::sim
