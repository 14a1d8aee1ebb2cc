#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/feature_frame.hpp"
#include "mcvio/core/imu_noise.hpp"
#include "mcvio/core/imu_sample.hpp"

namespace mcvio::estimator::testing {

/// Feature-level synthetic stereo-inertial sequence for estimator tests and benchmarks: a smooth
/// room-scale trajectory (still at the start), landmarks on the walls of a room, a 752x480 pinhole
/// stereo pair at 20 Hz, a 200 Hz IMU with white noise and bias random walk, perfect association.
struct SyntheticConfig {
  double duration_s = 20.0;
  double still_s = 2.0;             ///< the device rests this long before moving
  double pixel_noise_px = 1.0;      ///< sigma of the feature noise
  bool imu_noise = true;
  ImuNoiseParams noise;             ///< EuRoC ADIS16448 by default
  int num_landmarks = 4000;
  int max_features = 150;           ///< per frame (cam0)
  double motion_scale = 1.0;        ///< scales the trajectory amplitude
  Eigen::Vector3d gyro_bias0{0.003, -0.002, 0.004};
  Eigen::Vector3d accel_bias0{0.05, -0.04, 0.03};
  std::uint32_t seed = 1;
};

struct TruthState {
  Timestamp t = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d bg = Eigen::Vector3d::Zero(), ba = Eigen::Vector3d::Zero();
};

struct SyntheticSequence {
  std::vector<ImuSample> imu;
  std::vector<FeatureFrame> frames;
  std::vector<TruthState> truth;  ///< one per frame
  Eigen::Isometry3d T_BC0, T_BC1;
  double focal_px = 458.0;
  ImuNoiseParams noise;
};

SyntheticSequence generateSequence(const SyntheticConfig& config);

/// RMSE of position after the best yaw rotation + translation (4-DOF) alignment.
double ateAfterPositionYawAlignment(const std::vector<Eigen::Vector3d>& estimate, const std::vector<Eigen::Vector3d>& truth);

}  // namespace mcvio::estimator::testing

#include "mcvio/estimator/sliding_window_estimator.hpp"

namespace mcvio::estimator::testing {

/// Figures of one estimator run over a synthetic sequence.
struct RunResult {
  std::vector<EstimatorOutput> outputs;  ///< one per input frame
  int tracked_frames = 0;                ///< frames with status kTracking and an accepted state
  double ate_m = 0;                      ///< position+yaw aligned ATE RMSE over tracked frames
  double mean_position_nees = 0;         ///< over tracked frames with valid covariance
  double median_total_ms = 0;            ///< wall clock, as reported by the estimator
  double median_cpu_ms = 0;              ///< thread CPU time of addFrame (robust to a loaded machine)
  double p90_cpu_ms = 0;
  double max_abs_position_error_m = 0;   ///< unaligned
  int resets = 0;
};

/// Feeds IMU up to each frame time, then the frame.
RunResult runEstimator(const SyntheticSequence& seq, const EstimatorOptions& options);

}  // namespace mcvio::estimator::testing
