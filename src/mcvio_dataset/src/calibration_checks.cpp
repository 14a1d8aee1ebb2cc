#include "calibration_checks.hpp"

#include <sstream>

#include "number_format.hpp"

namespace mcvio::dataset::detail {

std::string intrinsicsProblem(const Eigen::Vector4d& in, int width, int height) {
  if (in[2] < 0 || in[2] > width || in[3] < 0 || in[3] > height) {
    return "principal point (" + std::to_string(in[2]) + ", " + std::to_string(in[3]) + ") lies outside the " +
           std::to_string(width) + "x" + std::to_string(height) + " image";
  }
  if (in[0] > 100.0 * width || in[1] > 100.0 * width) {
    return "focal length (" + std::to_string(in[0]) + ", " + std::to_string(in[1]) + ") is more than 100 image widths";
  }
  return {};
}

std::string distortionProblem(const CameraModel& m, const std::string& model_name) {
  if (m.distortionModel() == DistortionModel::kNone) return {};
  // Only the central half is checked: wide fisheye corners can lie beyond the model's 90 degrees.
  const double cu = m.cu(), cv = m.cv();
  const Eigen::Vector2d centre(cu, cv);
  const Eigen::Vector2d half_reach[4] = {{-0.5 * cu, 0.0}, {0.5 * (m.width() - cu), 0.0},
                                         {0.0, -0.5 * cv}, {0.0, 0.5 * (m.height() - cv)}};
  constexpr int kSteps = 16;
  for (const Eigen::Vector2d& reach : half_reach) {
    for (int i = 1; i <= kSteps; ++i) {
      const Eigen::Vector2d pixel = centre + reach * (static_cast<double>(i) / kSteps);
      Eigen::Vector2d normalized, back;
      const bool inverts = m.unproject(pixel, &normalized) &&
                           m.projectAnywhere(Eigen::Vector3d(normalized.x(), normalized.y(), 1.0), &back) &&
                           (back - pixel).norm() < 0.01;
      std::ostringstream os;
      if (!inverts) {
        os << "cannot be inverted at pixel (" << pixel.x() << ", " << pixel.y()
           << ") in the central half of the image: the " << model_name
           << " model folds over there and features would be lost (a unit or sign slip?)";
        return os.str();
      }
      const double scale = m.pixelToDistorted(pixel).norm() / normalized.norm();
      if (scale > 5.0 || scale < 0.2) {
        os << "scale the ray through pixel (" << pixel.x() << ", " << pixel.y() << ") by " << scale
           << ", in the central half of the image; a real lens stays within 0.2-5 there (a unit or sign slip?)";
        return os.str();
      }
    }
  }
  return {};
}

std::string transformProblem(const Eigen::Matrix4d& m) {
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) return "last row must be [0, 0, 0, 1]";
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  const double orthogonality = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (orthogonality > 1e-5 || R.determinant() < 0.0) {
    return "rotation part is not a rotation matrix (|R^T R - I| = " + formatDouble(orthogonality) + ")";
  }
  return {};
}

}  // namespace mcvio::dataset::detail
