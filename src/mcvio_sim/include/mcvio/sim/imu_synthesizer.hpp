#pragma once
#include <cstdint>
#include <vector>

#include "mcvio/core/imu_noise.hpp"
#include "mcvio/core/imu_sample.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"
#include "mcvio/sim/trajectory.hpp"

namespace mcvio::sim {

/// Standard gravity in the z-up world frame [m/s^2].
inline const Eigen::Vector3d kGravityW(0.0, 0.0, -9.81);

/// IMU measurements and the matching ground truth at the IMU rate.
struct ImuSequence {
  std::vector<ImuSample> samples;
  std::vector<dataset::GroundTruthState> ground_truth;  ///< same timestamps, with the true biases
};

/// Synthesises a body-frame IMU from a trajectory's exact derivatives:
///   gyro  = omega_b + b_g + n_g,   accel = R_wb^T (a_w - g) + b_a + n_a,
/// with white noise of density sigma_c (discrete sigma_c / sqrt(dt)) and biases that follow a
/// random walk (discrete step sigma_rw * sqrt(dt)), reproducible for a seed.
class ImuSynthesizer {
 public:
  struct Options {
    ImuNoiseParams noise;  ///< EuRoC ADIS16448 by default; noise.rate_hz is the IMU rate
    bool add_noise = true;  ///< false: exact measurements, biases stay at their initial values
    Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d::Zero();   ///< [rad/s]
    Eigen::Vector3d initial_accel_bias = Eigen::Vector3d::Zero();  ///< [m/s^2]
    std::uint64_t seed = 1;
  };

  explicit ImuSynthesizer(Options options);

  /// Samples at start, start + 1/rate, ... up to and including `end` if it falls on the grid.
  ImuSequence synthesize(const Trajectory& trajectory, Timestamp start, Timestamp end) const;

  /// Exact specific force and angular rate for one state (no bias, no noise).
  static ImuSample idealMeasurement(const KinematicState& state, Timestamp t);

 private:
  Options options_;
};

}  // namespace mcvio::sim
