#pragma once

namespace mcvio {

/// Continuous-time IMU noise model as in EuRoC's imu0/sensor.yaml. Defaults: ADIS16448 (EuRoC).
/// Discrete white noise per sample is density / sqrt(dt); bias random walk per sample is
/// random_walk * sqrt(dt).
struct ImuNoiseParams {
  double gyroscope_noise_density = 1.6968e-04;      ///< [rad/s/sqrt(Hz)]
  double gyroscope_random_walk = 1.9393e-05;        ///< [rad/s^2/sqrt(Hz)]
  double accelerometer_noise_density = 2.0000e-03;  ///< [m/s^2/sqrt(Hz)]
  double accelerometer_random_walk = 3.0000e-03;    ///< [m/s^3/sqrt(Hz)]
  double rate_hz = 200.0;
};

}  // namespace mcvio
