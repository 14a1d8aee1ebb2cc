#pragma once
// Internal to mcvio_components: the sensor topics a calibration names (Kalibr's rostopic).
#include <iostream>
#include <string>

#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/dds/node.hpp"

namespace mcvio::components::detail {

/// Reads each sensor from the topic it was calibrated on, as OpenVINS does with Kalibr's
/// rostopic, unless a --remap rule already names that sensor's topic. `cameras`: the frontend's
/// images as well as /imu0. Says so on stderr for every topic it changes.
inline void remapToCalibratedTopics(dds::Node& node, const StereoRigCalibration& rig, bool cameras, const std::string& component) {
  const auto take = [&](const std::string& topic, const std::string& calibrated, const std::string& sensor) {
    if (calibrated.empty() || calibrated == topic || !node.remapByDefault(topic, calibrated)) return;
    std::cerr << "mcvio " << component << ": reading " << topic << " from " << calibrated << ", " << sensor
              << "'s rostopic in the calibration (--remap " << topic << ":=" << topic << " keeps the default)\n";
  };
  if (cameras) {
    take("/cam0/image_raw", rig.cam0.topic, "cam0");
    take("/cam1/image_raw", rig.cam1.topic, "cam1");
  }
  take("/imu0", rig.imu.topic, "the IMU");
}

}  // namespace mcvio::components::detail
