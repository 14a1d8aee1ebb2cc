#pragma once
#include "mcvio/core/stereo_rig_calibration.hpp"

namespace mcvio::sim {

/// The EuRoC MAV rig (VI-Sensor) as in the V1_01 cam0/cam1/imu0 sensor.yaml files: 752x480
/// pinhole + radial-tangential cameras at 20 Hz, ~11 cm baseline, ADIS16448 IMU at 200 Hz.
StereoRigCalibration eurocRigDefaults();

}  // namespace mcvio::sim
