#include "mcvio/core/camera_model.hpp"

#include <Eigen/LU>
#include <cmath>
#include <sstream>

#include "mcvio/core/input_error.hpp"

namespace mcvio {

namespace {

constexpr int kMaxUndistortIterations = 50;
// Newton stops once the distorted-coordinate residual is this small; success needs < 1e-10.
constexpr double kUndistortTolerance = 1e-15;
constexpr double kUndistortAcceptance = 1e-10;
// Below this radius the equidistant mapping is the identity to double precision.
constexpr double kTinyRadius = 1e-10;

// theta_d(theta) = theta (1 + k1 t^2 + k2 t^4 + k3 t^6 + k4 t^8) and its derivative.
void equidistantPolynomial(const Eigen::Vector4d& k, double theta, double* theta_d,
                           double* dtheta_d) {
  const double t2 = theta * theta;
  const double t4 = t2 * t2;
  const double t6 = t4 * t2;
  const double t8 = t4 * t4;
  *theta_d = theta * (1.0 + k[0] * t2 + k[1] * t4 + k[2] * t6 + k[3] * t8);
  *dtheta_d = 1.0 + 3.0 * k[0] * t2 + 5.0 * k[1] * t4 + 7.0 * k[2] * t6 + 9.0 * k[3] * t8;
}

}  // namespace

const char* toString(DistortionModel model) {
  switch (model) {
    case DistortionModel::kNone:
      return "none";
    case DistortionModel::kRadialTangential:
      return "radial-tangential";
    case DistortionModel::kEquidistant:
      return "equidistant";
    case DistortionModel::kDoubleSphere:
      return "double-sphere";
    case DistortionModel::kExtendedUnified:
      return "extended-unified";
  }
  return "none";
}

DistortionModel distortionModelFromString(const std::string& name) {
  if (name == "radial-tangential" || name == "radtan" || name == "plumb_bob") {
    return DistortionModel::kRadialTangential;
  }
  if (name == "equidistant" || name == "fisheye") return DistortionModel::kEquidistant;
  if (name == "none" || name == "pinhole") return DistortionModel::kNone;
  if (name == "double-sphere" || name == "double_sphere" || name == "ds") return DistortionModel::kDoubleSphere;
  if (name == "extended-unified" || name == "extended_unified" || name == "eucm") {
    return DistortionModel::kExtendedUnified;
  }
  throw InputError("unknown distortion model '" + name +
                   "' (expected radial-tangential, equidistant, double-sphere, extended-unified or none)");
}

int distortionCoefficientCount(DistortionModel model) {
  switch (model) {
    case DistortionModel::kNone:
      return 0;
    case DistortionModel::kDoubleSphere:
    case DistortionModel::kExtendedUnified:
      return 2;
    default:
      return 4;
  }
}

bool isProjectionModel(DistortionModel model) {
  return model == DistortionModel::kDoubleSphere || model == DistortionModel::kExtendedUnified;
}

PixelScale pixelScaleFromString(const std::string& name) {
  if (name == "centre") return PixelScale::kCentre;
  if (name == "local") return PixelScale::kLocal;
  if (name == "wide_angle") return PixelScale::kWideAngle;
  throw InputError("key 'pixel_scale': unknown pixel scale '" + name + "' (expected centre, local or wide_angle)");
}

bool usesLocalPixelScale(PixelScale scale, DistortionModel model) {
  switch (scale) {
    case PixelScale::kCentre:
      return false;
    case PixelScale::kLocal:
      return true;
    case PixelScale::kWideAngle:
      return model == DistortionModel::kEquidistant || isProjectionModel(model);
  }
  return false;
}

CameraModel::CameraModel(int width, int height, const Vec4& intrinsics, DistortionModel model,
                         const Vec4& coefficients)
    : width_(width),
      height_(height),
      intrinsics_(intrinsics),
      model_(model),
      coefficients_(model == DistortionModel::kNone ? Vec4::Zero() : coefficients) {
  if (width <= 0 || height <= 0) {
    std::ostringstream os;
    os << "camera resolution must be positive, got " << width << "x" << height;
    throw InputError(os.str());
  }
  if (!intrinsics.allFinite() || !(intrinsics[0] > 0.0) || !(intrinsics[1] > 0.0)) {
    std::ostringstream os;
    os << "camera intrinsics must be finite with positive focal lengths, got ["
       << intrinsics.transpose() << "]";
    throw InputError(os.str());
  }
  if (!coefficients_.allFinite()) {
    throw InputError("camera distortion coefficients must be finite");
  }
  const auto outside = [](const char* what, double value, const char* range) {
    std::ostringstream os;
    os << what << " = " << value << " is outside " << range;
    throw InputError(os.str());
  };
  if (model == DistortionModel::kDoubleSphere) {
    // At xi = -1 every ray through the centre lands on one pixel.
    if (!(coefficients_[0] > -1.0 && coefficients_[0] <= 1.0)) outside("double sphere xi", coefficients_[0], "(-1, 1]");
    if (!(coefficients_[1] >= 0.0 && coefficients_[1] <= 1.0)) outside("double sphere alpha", coefficients_[1], "[0, 1]");
  } else if (model == DistortionModel::kExtendedUnified) {
    if (!(coefficients_[0] >= 0.0 && coefficients_[0] <= 1.0)) outside("extended unified alpha", coefficients_[0], "[0, 1]");
    if (!(coefficients_[1] > 0.0)) outside("extended unified beta", coefficients_[1], "(0, inf)");
  }
  if (distortionCoefficientCount(model) == 2) coefficients_.tail<2>().setZero();
}

void CameraModel::wideAngleDenominator(double r, double* den, double* dden_dr) const {
  const double a = model_ == DistortionModel::kDoubleSphere ? coefficients_[1] : coefficients_[0];
  if (model_ == DistortionModel::kDoubleSphere) {
    const double xi = coefficients_[0];
    const double d1 = std::sqrt(r * r + 1.0);
    const double k = xi * d1 + 1.0, dk = xi * r / d1;
    const double d2 = std::sqrt(r * r + k * k), dd2 = (r + k * dk) / d2;
    *den = a * d2 + (1.0 - a) * k;
    *dden_dr = a * dd2 + (1.0 - a) * dk;
  } else {
    const double beta = coefficients_[1];
    const double rho = std::sqrt(beta * r * r + 1.0);
    *den = a * rho + 1.0 - a;
    *dden_dr = a * beta * r / rho;
  }
}

CameraModel::Vec2 CameraModel::distort(const Vec2& p, Eigen::Matrix2d* J) const {
  const Vec4& k = coefficients_;
  switch (model_) {
    case DistortionModel::kNone:
      if (J) J->setIdentity();
      return p;
    case DistortionModel::kRadialTangential: {
      const double x = p.x(), y = p.y();
      const double xy = x * y, x2 = x * x, y2 = y * y;
      const double r2 = x2 + y2;
      const double radial = 1.0 + r2 * (k[0] + k[1] * r2);
      const double k1p = k[0] + 2.0 * k[1] * r2;  // d radial / d r2
      if (J) {
        const double cross = 2.0 * xy * k1p + 2.0 * k[2] * x + 2.0 * k[3] * y;
        (*J)(0, 0) = radial + 2.0 * x2 * k1p + 2.0 * k[2] * y + 6.0 * k[3] * x;
        (*J)(0, 1) = cross;
        (*J)(1, 0) = cross;
        (*J)(1, 1) = radial + 2.0 * y2 * k1p + 6.0 * k[2] * y + 2.0 * k[3] * x;
      }
      return Vec2(x * radial + 2.0 * k[2] * xy + k[3] * (r2 + 2.0 * x2),
                  y * radial + k[2] * (r2 + 2.0 * y2) + 2.0 * k[3] * xy);
    }
    case DistortionModel::kEquidistant: {
      const double r = p.norm();
      if (r < kTinyRadius) {
        if (J) J->setIdentity();
        return p;
      }
      const double theta = std::atan(r);
      double theta_d, dtheta_d;
      equidistantPolynomial(k, theta, &theta_d, &dtheta_d);
      const double s = theta_d / r;
      if (J) {
        // d s / d r, with d theta / d r = 1 / (1 + r^2).
        const double ds_dr = (dtheta_d / (1.0 + r * r) - s) / r;
        *J = s * Eigen::Matrix2d::Identity() + (ds_dr / r) * p * p.transpose();
      }
      return s * p;
    }
    case DistortionModel::kDoubleSphere:
    case DistortionModel::kExtendedUnified: {
      const double r = p.norm();
      double den, dden;
      wideAngleDenominator(r, &den, &dden);
      const double s = 1.0 / den;
      if (J) {
        *J = s * Eigen::Matrix2d::Identity();
        // d s / d r = -dden / den^2, and d r / d p = p^T / r.
        if (r > kTinyRadius) *J -= (dden / (den * den * r)) * p * p.transpose();
      }
      return s * p;
    }
  }
  return p;
}

bool CameraModel::undistortWideAngle(const Vec2& m, Vec2* undistorted) const {
  // The models' closed-form unprojections, then the ray's normalised coordinates.
  const double r2 = m.squaredNorm();
  Eigen::Vector3d ray;
  if (model_ == DistortionModel::kDoubleSphere) {
    const double xi = coefficients_[0], a = coefficients_[1];
    const double root = 1.0 - (2.0 * a - 1.0) * r2;
    if (!(root >= 0.0)) return false;  // beyond the image circle of alpha > 1/2
    const double mz = (1.0 - a * a * r2) / (a * std::sqrt(root) + 1.0 - a);
    const double inner = mz * mz + (1.0 - xi * xi) * r2;
    if (!(inner >= 0.0)) return false;
    const double scale = (mz * xi + std::sqrt(inner)) / (mz * mz + r2);
    ray = Eigen::Vector3d(scale * m.x(), scale * m.y(), scale * mz - xi);
  } else {
    const double a = coefficients_[0], beta = coefficients_[1];
    const double root = 1.0 - (2.0 * a - 1.0) * beta * r2;
    if (!(root >= 0.0)) return false;
    const double mz = (1.0 - beta * a * a * r2) / (a * std::sqrt(root) + 1.0 - a);
    ray = Eigen::Vector3d(m.x(), m.y(), mz);
  }
  if (!ray.allFinite() || !(ray.z() > 1e-9 * ray.norm())) return false;  // at or beyond 90 degrees
  const Vec2 p = ray.head<2>() / ray.z();
  if (!p.allFinite() || !inValidRange(p)) return false;
  // The closed forms hold inside the model's valid region only; the forward map confirms it.
  if (!((distort(p) - m).norm() < kUndistortAcceptance * (1.0 + m.norm()))) return false;
  *undistorted = p;
  return true;
}

bool CameraModel::undistort(const Vec2& distorted, Vec2* undistorted) const {
  if (!distorted.allFinite()) return false;
  switch (model_) {
    case DistortionModel::kNone:
      *undistorted = distorted;
      return true;
    case DistortionModel::kEquidistant: {
      // One-dimensional Newton on theta_d(theta) = |distorted|; the direction is unchanged.
      const double theta_d = distorted.norm();
      if (theta_d < kTinyRadius) {
        *undistorted = distorted;
        return true;
      }
      double theta = theta_d;
      bool converged = false;
      for (int i = 0; i < kMaxUndistortIterations; ++i) {
        double f, df;
        equidistantPolynomial(coefficients_, theta, &f, &df);
        if (!(df > 0.0)) return false;
        const double step = (f - theta_d) / df;
        theta -= step;
        if (std::abs(step) < kUndistortTolerance * (1.0 + theta)) {
          converged = true;
          break;
        }
      }
      if (!std::isfinite(theta) || theta < 0.0 || theta >= M_PI / 2) return false;
      double f, df;
      equidistantPolynomial(coefficients_, theta, &f, &df);
      if (!converged && std::abs(f - theta_d) > kUndistortAcceptance) return false;
      *undistorted = distorted * (std::tan(theta) / theta_d);
      return true;
    }
    case DistortionModel::kDoubleSphere:
    case DistortionModel::kExtendedUnified:
      return undistortWideAngle(distorted, undistorted);
    case DistortionModel::kRadialTangential: {
      Vec2 p = distorted;  // start at the distorted point: distortion is a small perturbation
      Eigen::Matrix2d J;
      double residual_norm = 0.0;
      for (int i = 0; i < kMaxUndistortIterations; ++i) {
        const Vec2 residual = distort(p, &J) - distorted;
        residual_norm = residual.norm();
        if (residual_norm < kUndistortTolerance) break;
        const double det = J.determinant();
        if (!(std::abs(det) > 1e-12)) return false;
        p -= J.inverse() * residual;
        if (!p.allFinite()) return false;
      }
      residual_norm = (distort(p, &J) - distorted).norm();
      if (!(residual_norm < kUndistortAcceptance) || !inValidRange(p)) return false;
      *undistorted = p;
      return true;
    }
  }
  return false;
}

bool CameraModel::inValidRange(const Vec2& p) const {
  // Beyond the fold of the distortion polynomial two directions map to one pixel; a positive
  // Jacobian determinant keeps the mapping one-to-one.
  if (model_ == DistortionModel::kNone) return true;
  if (isProjectionModel(model_)) {
    double den, dden;
    wideAngleDenominator(p.norm(), &den, &dden);
    if (!(den > 0.0)) return false;
  }
  Eigen::Matrix2d J;
  distort(p, &J);
  return J.determinant() > 0.0;
}

bool CameraModel::projectAnywhere(const Vec3& p_C, Vec2* pixel,
                                  Eigen::Matrix<double, 2, 3>* J) const {
  const double z = p_C.z();
  if (!(z > 0.0) || !p_C.allFinite()) return false;
  const double inv_z = 1.0 / z;
  const Vec2 n(p_C.x() * inv_z, p_C.y() * inv_z);
  Eigen::Matrix2d Jd;
  const Vec2 d = distort(n, J ? &Jd : nullptr);
  *pixel = distortedToPixel(d);
  if (J) {
    Eigen::Matrix<double, 2, 3> Jn;
    Jn << inv_z, 0.0, -n.x() * inv_z, 0.0, inv_z, -n.y() * inv_z;
    Eigen::Matrix<double, 2, 3> Jdn = Jd * Jn;
    Jdn.row(0) *= intrinsics_[0];
    Jdn.row(1) *= intrinsics_[1];
    *J = Jdn;
  }
  return inValidRange(n);
}

bool CameraModel::project(const Vec3& p_C, Vec2* pixel, Eigen::Matrix<double, 2, 3>* J) const {
  return projectAnywhere(p_C, pixel, J) && isInImage(*pixel);
}

bool CameraModel::unproject(const Vec2& pixel, Vec2* normalized) const {
  return undistort(pixelToDistorted(pixel), normalized);
}

bool CameraModel::unprojectBearing(const Vec2& pixel, Vec3* bearing) const {
  Vec2 n;
  if (!unproject(pixel, &n)) return false;
  *bearing = Vec3(n.x(), n.y(), 1.0).normalized();
  return true;
}

CameraModel::Vec2 CameraModel::pixelToDistorted(const Vec2& pixel) const {
  return Vec2((pixel.x() - intrinsics_[2]) / intrinsics_[0],
              (pixel.y() - intrinsics_[3]) / intrinsics_[1]);
}

CameraModel::Vec2 CameraModel::distortedToPixel(const Vec2& d) const {
  return Vec2(intrinsics_[0] * d.x() + intrinsics_[2], intrinsics_[1] * d.y() + intrinsics_[3]);
}

bool CameraModel::isInImage(const Vec2& pixel, double border) const {
  return pixel.x() >= -0.5 + border && pixel.x() < width_ - 0.5 - border &&
         pixel.y() >= -0.5 + border && pixel.y() < height_ - 0.5 - border;
}

double CameraModel::focalLengthAtCentre() const {
  const double f = 0.5 * (intrinsics_[0] + intrinsics_[1]);
  return model_ == DistortionModel::kDoubleSphere ? f / (1.0 + coefficients_[0]) : f;
}

double CameraModel::pixelScaleAt(const Vec2& normalised) const {
  return std::sqrt(std::abs(pixelJacobianAt(normalised).determinant()));
}

Eigen::Matrix2d CameraModel::pixelJacobianAt(const Vec2& normalised) const {
  Eigen::Matrix2d J;
  distort(normalised, &J);
  J.row(0) *= intrinsics_[0];
  J.row(1) *= intrinsics_[1];
  return J;
}

Eigen::Matrix3d CameraModel::cameraMatrix() const {
  Eigen::Matrix3d K;
  K << intrinsics_[0], 0.0, intrinsics_[2], 0.0, intrinsics_[1], intrinsics_[3], 0.0, 0.0, 1.0;
  return K;
}

}  // namespace mcvio
