#include "camera_model_fields.hpp"

namespace mcvio::dataset::detail {

bool projectionNamed(const std::string& camera_model, ProjectionFields* fields, std::string* problem) {
  if (camera_model == "pinhole") {
    *fields = {DistortionModel::kNone, 4};
  } else if (camera_model == "ds") {
    *fields = {DistortionModel::kDoubleSphere, 6};
  } else if (camera_model == "eucm") {
    *fields = {DistortionModel::kExtendedUnified, 6};
  } else {
    *problem = "'" + camera_model + "' is not supported (pinhole, ds or eucm" +
               (camera_model == "omni" ? std::string("; omni, the unified model with a distortion on top, is not: "
                                                     "calibrate the lens as ds or eucm)")
                                       : std::string(")"));
    return false;
  }
  return true;
}

void splitIntrinsics(const ProjectionFields& fields, const std::vector<double>& listed, Eigen::Vector4d* intrinsics,
                     Eigen::Vector4d* coefficients) {
  const std::size_t shape = fields.intrinsics_count - 4;
  *intrinsics = Eigen::Vector4d(listed[shape], listed[shape + 1], listed[shape + 2], listed[shape + 3]);
  *coefficients = Eigen::Vector4d::Zero();
  for (std::size_t i = 0; i < shape; ++i) (*coefficients)[static_cast<Eigen::Index>(i)] = listed[i];
}

const char* cameraModelName(const CameraModel& model) {
  switch (model.distortionModel()) {
    case DistortionModel::kDoubleSphere:
      return "ds";
    case DistortionModel::kExtendedUnified:
      return "eucm";
    default:
      return "pinhole";
  }
}

std::vector<double> listedIntrinsics(const CameraModel& model) {
  std::vector<double> listed;
  if (isProjectionModel(model.distortionModel())) {
    listed = {model.distortionCoefficients()[0], model.distortionCoefficients()[1]};
  }
  for (int i = 0; i < 4; ++i) listed.push_back(model.intrinsics()[i]);
  return listed;
}

}  // namespace mcvio::dataset::detail
