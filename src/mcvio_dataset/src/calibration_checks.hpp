#pragma once
// Plausibility checks shared by the calibration readers (EuRoC sensor.yaml, Kalibr camchain);
// internal to mcvio_dataset. Each returns an empty string when the value is plausible, otherwise
// the reason, for the reader to put after the file and key.
#include <string>

#include <Eigen/Geometry>

#include "mcvio/core/camera_model.hpp"

namespace mcvio::dataset::detail {

/// A real lens's principal point lies inside its image, and a focal length beyond 100 image
/// widths is a unit slip: both would run and silently lose every feature.
std::string intrinsicsProblem(const Eigen::Vector4d& intrinsics, int width, int height);

/// A real lens's distortion inverts over the central half of its image and stretches it by
/// well under 5x; a unit or sign slip (k1 = 1e6) folds the model there. `model_name` as the file
/// spells it.
std::string distortionProblem(const CameraModel& model, const std::string& model_name);

/// A 4x4 rigid transform: last row [0, 0, 0, 1], rotation part a rotation matrix.
std::string transformProblem(const Eigen::Matrix4d& m);

}  // namespace mcvio::dataset::detail
