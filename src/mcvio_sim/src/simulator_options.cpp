#include "mcvio/sim/simulator_options.hpp"

#include <yaml-cpp/yaml.h>

#include "mcvio/core/yaml_fields.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::sim {
namespace {

void requireRange(bool ok, const std::string& key, const std::string& rule) { requireOption(ok, "option", key, rule); }

}  // namespace

SimulatorOptions SimulatorOptions::fromYaml(const YAML::Node& node) {
  SimulatorOptions o;
  YamlFields f(node, "");
  f.get("output_dir", &o.output_dir);
  f.get("overwrite", &o.overwrite);
  f.get("seed", &o.seed);
  f.get("duration_s", &o.duration_s);
  f.get("start_time_ns", &o.start_time_ns);
  f.get("camera_rate_hz", &o.camera_rate_hz);
  f.get("threads", &o.threads);
  f.get("texture_size", &o.texture_size);
  f.get("calibration_dir", &o.calibration_dir);

  YamlFields sc(f.child("scenario"), "scenario.");
  std::string kind = toString(o.scenario.kind);
  sc.get("kind", &kind);
  o.scenario.kind = scenarioKindFromString(kind);
  sc.get("onset_s", &o.scenario.onset_s);
  sc.get("duration_s", &o.scenario.duration_s);
  sc.get("coverage", &o.scenario.coverage);
  sc.get("travel_m", &o.scenario.travel_m);
  sc.rejectUnknown();

  YamlFields imu(f.child("imu"), "imu.");
  imu.get("noise", &o.imu_noise_enabled);
  imu.get("rate_hz", &o.imu_noise.rate_hz);
  imu.get("gyroscope_noise_density", &o.imu_noise.gyroscope_noise_density);
  imu.get("gyroscope_random_walk", &o.imu_noise.gyroscope_random_walk);
  imu.get("accelerometer_noise_density", &o.imu_noise.accelerometer_noise_density);
  imu.get("accelerometer_random_walk", &o.imu_noise.accelerometer_random_walk);
  imu.getVector3("initial_gyro_bias", &o.initial_gyro_bias);
  imu.getVector3("initial_accel_bias", &o.initial_accel_bias);
  imu.rejectUnknown();

  YamlFields img(f.child("image"), "image.");
  img.get("noise_sigma", &o.pixel_noise_sigma);
  img.get("gain_drift", &o.gain_drift);
  img.get("gain_period_s", &o.gain_period_s);
  img.get("png_compression", &o.png_compression);
  std::string filter = toString(o.texture_filter);
  img.get("texture_filter", &filter);
  o.texture_filter = textureFilterFromString(filter, "image.texture_filter");
  img.rejectUnknown();

  YamlFields semi(f.child("semi_real"), "semi_real.");
  semi.get("groundtruth_csv", &o.groundtruth_csv);
  semi.get("imu_csv", &o.imu_csv);
  semi.rejectUnknown();

  f.rejectUnknown();
  o.validate();
  return o;
}

SimulatorOptions SimulatorOptions::fromYamlFile(const std::string& path) {
  return loadOptionsFile(path, [](const YAML::Node& node) { return fromYaml(node); });
}

void SimulatorOptions::validate() const {
  requireRange(duration_s > 0.5 && duration_s <= 3600, "duration_s", "must be in (0.5, 3600]");
  requireRange(start_time_ns >= 0, "start_time_ns", "must not be negative");
  requireRange(camera_rate_hz > 0 && camera_rate_hz <= 200, "camera_rate_hz", "must be in (0, 200]");
  requireRange(threads >= 1 && threads <= 64, "threads", "must be in [1, 64]");
  requireRange(texture_size >= 16 && texture_size <= 4096 && (texture_size & (texture_size - 1)) == 0,
               "texture_size", "must be a power of two in [16, 4096]");
  requireRange(scenario.onset_s >= 0, "scenario.onset_s", "must not be negative");
  requireRange(scenario.duration_s >= 0, "scenario.duration_s", "must not be negative");
  requireRange(scenario.coverage > 0 && scenario.coverage <= 1, "scenario.coverage", "must be in (0, 1]");
  requireRange(imu_noise.rate_hz > 0 && imu_noise.rate_hz <= 10000, "imu.rate_hz", "must be in (0, 10000]");
  requireRange(imu_noise.gyroscope_noise_density >= 0, "imu.gyroscope_noise_density", "must not be negative");
  requireRange(imu_noise.gyroscope_random_walk >= 0, "imu.gyroscope_random_walk", "must not be negative");
  requireRange(imu_noise.accelerometer_noise_density >= 0, "imu.accelerometer_noise_density", "must not be negative");
  requireRange(imu_noise.accelerometer_random_walk >= 0, "imu.accelerometer_random_walk", "must not be negative");
  requireRange(pixel_noise_sigma >= 0 && pixel_noise_sigma <= 50, "image.noise_sigma", "must be in [0, 50]");
  requireRange(gain_drift >= 0 && gain_drift < 0.9, "image.gain_drift", "must be in [0, 0.9)");
  requireRange(gain_period_s > 0, "image.gain_period_s", "must be positive");
  requireRange(png_compression >= 0 && png_compression <= 9, "image.png_compression", "must be in [0, 9]");
  requireRange(groundtruth_csv.empty() == imu_csv.empty(), groundtruth_csv.empty() ? "semi_real.groundtruth_csv" : "semi_real.imu_csv",
               "must be set together with the other semi_real file");
  if (!semiReal() && scenario.kind != ScenarioKind::kNone)
    requireRange(scenario.onset_s + scenario.duration_s <= duration_s + 1e-9, "scenario.duration_s",
                 "makes the conflict end after the sequence (onset_s + duration_s > duration_s)");
}

}  // namespace mcvio::sim
