#pragma once
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "mcvio/core/imu_noise.hpp"
#include "mcvio/core/time.hpp"
#include "mcvio/sim/camera_renderer.hpp"
#include "mcvio/sim/scenario_options.hpp"

namespace YAML {
class Node;
}

namespace mcvio::sim {

/// Everything `mcvio sim` needs. Defaults give a 60 s EuRoC-like sequence of a textured office
/// without conflict. YAML keys are the member names, grouped as in the example below; every key
/// is optional, unknown keys are errors.
///
///   output_dir: /tmp/sim_elevator
///   seed: 7
///   duration_s: 60
///   scenario: {kind: elevator, onset_s: 20, duration_s: 15, coverage: 1.0, travel_m: 12}
///   imu: {noise: true, gyroscope_noise_density: 1.6968e-4, initial_gyro_bias: [0, 0, 0]}
///   image: {noise_sigma: 2.0, gain_drift: 0.15, png_compression: 0, texture_filter: isotropic}
///   semi_real: {groundtruth_csv: .../data.csv, imu_csv: .../data.csv}
///   calibration_dir: /data/V1_01_easy/mav0
struct SimulatorOptions {
  std::string output_dir;      ///< EuRoC folder to write (mav0/ is created inside)
  bool overwrite = false;      ///< replace an existing output_dir/mav0
  std::uint64_t seed = 1;      ///< world layout, textures, IMU noise, pixel noise
  double duration_s = 60.0;    ///< synthetic trajectory length (semi-real: the recording's)
  Timestamp start_time_ns = 1600000000000000000;  ///< first timestamp of a synthetic sequence
  double camera_rate_hz = 20.0;
  int threads = 2;             ///< rendering threads
  int texture_size = 1024;     ///< texels per procedural texture edge (power of two)
  /// Folder with cam0/, cam1/ (and imu0/) sensor.yaml, or the folder holding mav0/. Empty: the
  /// EuRoC V1_01 calibration (752x480 radial-tangential, 11 cm baseline).
  std::string calibration_dir;

  ScenarioOptions scenario;

  ImuNoiseParams imu_noise;    ///< used to synthesise the IMU and written to imu0/sensor.yaml
  bool imu_noise_enabled = true;  ///< false: exact IMU (biases stay at their initial values)
  Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d initial_accel_bias = Eigen::Vector3d::Zero();

  double pixel_noise_sigma = 2.0;  ///< additive image noise [grey levels]
  double gain_drift = 0.15;        ///< relative amplitude of the slow exposure/gain change
  double gain_period_s = 23.0;     ///< period of that change [s]
  /// zlib level of the written PNGs (lossless at any level). 0 stores them as EuRoC does: noisy
  /// images hardly compress (227 instead of 362 KB at level 1) but decode 2x slower (5 vs 2.3 ms).
  int png_compression = 0;
  /// How a pixel averages the texture under it (`image.texture_filter`); see TextureFilter.
  /// isotropic overstates the footprint towards the edges of wide lenses; it stays the default
  /// while the benchmarks' figures are measured on its images.
  TextureFilter texture_filter = TextureFilter::kIsotropic;

  /// Semi-real mode when both are set: render along this EuRoC ground truth
  /// (state_groundtruth_estimate0/data.csv) and keep this real IMU (imu0/data.csv); elevator and
  /// vehicle rides are added to both.
  std::string groundtruth_csv;
  std::string imu_csv;

  bool semiReal() const { return !groundtruth_csv.empty() || !imu_csv.empty(); }

  /// Reads the keys present in `node` over the defaults; throws mcvio::InputError naming the
  /// key for wrong types or unknown keys, then validate()s.
  static SimulatorOptions fromYaml(const YAML::Node& node);
  /// Same from a file; errors also name the file.
  static SimulatorOptions fromYamlFile(const std::string& path);
  /// Throws mcvio::InputError naming the first key whose value is out of range.
  void validate() const;
};

}  // namespace mcvio::sim
