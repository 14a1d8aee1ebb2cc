#pragma once
// How calibration files (Kalibr's camchain, mcvio's sensor.yaml) spell a camera model (internal
// to mcvio_dataset): camera_model names the projection, intrinsics lists its parameters,
// distortion_model the pinhole's lens distortion. Kalibr's ds and eucm list their two shape
// parameters before the focal lengths and take distortion_model none.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mcvio/core/camera_model.hpp"

namespace mcvio::dataset::detail {

/// A camera_model mcvio reads.
struct ProjectionFields {
  DistortionModel wide_angle = DistortionModel::kNone;  ///< kNone for pinhole
  std::size_t intrinsics_count = 4;                    ///< 4 for pinhole, 6 for ds and eucm
};

/// "pinhole", "ds" or "eucm"; otherwise the reason for the reader to put after the key.
bool projectionNamed(const std::string& camera_model, ProjectionFields* fields, std::string* problem);

/// The listed intrinsics split into (fu, fv, cu, cv) and a wide-angle model's coefficients
/// ((xi, alpha, 0, 0) for ds, (alpha, beta, 0, 0) for eucm; zeros for pinhole).
void splitIntrinsics(const ProjectionFields& fields, const std::vector<double>& listed, Eigen::Vector4d* intrinsics,
                     Eigen::Vector4d* coefficients);

/// The camera_model a file names for `model`: "pinhole", "ds" or "eucm".
const char* cameraModelName(const CameraModel& model);

/// The intrinsics as a file lists them: [fu, fv, cu, cv], or [xi, alpha | alpha, beta, fu, fv, cu, cv].
std::vector<double> listedIntrinsics(const CameraModel& model);

}  // namespace mcvio::dataset::detail
