#pragma once
#include <Eigen/Core>
#include <string>

namespace mcvio {

/// The lens: how normalised image coordinates (x/z, y/z) map to the distorted coordinates that
/// the focal lengths and principal point turn into pixels. The first three are a pinhole with
/// lens distortion, named as in EuRoC/Kalibr sensor.yaml files; the last two are the wide-angle
/// projection models of Usenko et al. 2018 (Basalt, Kalibr's `ds` and `eucm`), which replace the
/// pinhole. Written on normalised coordinates, every model covers the rays in front of the
/// camera (under 90 degrees off-axis), as the estimator does.
enum class DistortionModel {
  kNone,              ///< ideal pinhole, no coefficients
  kRadialTangential,  ///< "radial-tangential" (plumb bob): k1 k2 p1 p2
  kEquidistant,       ///< "equidistant" (Kannala-Brandt fisheye): k1 k2 k3 k4
  kDoubleSphere,      ///< "double-sphere" (Kalibr's ds): xi in (-1, 1], alpha in [0, 1]
  kExtendedUnified,   ///< "extended-unified" (Kalibr's eucm): alpha in [0, 1], beta > 0
};

/// "none", "radial-tangential", "equidistant", "double-sphere" or "extended-unified".
const char* toString(DistortionModel model);
/// Parses the sensor.yaml spelling (also accepts "radtan", "plumb_bob", "fisheye", "pinhole"
/// for none, "ds" and "eucm"); throws mcvio::InputError naming the value otherwise.
DistortionModel distortionModelFromString(const std::string& name);
/// Number of coefficients the model takes: 0 (none), 4 (radial-tangential, equidistant) or 2
/// (double sphere: xi alpha; extended unified: alpha beta).
int distortionCoefficientCount(DistortionModel model);
/// True for the double sphere and extended unified models, which replace the pinhole rather
/// than distort it (calibration files name them as the camera_model, not the distortion_model).
bool isProjectionModel(DistortionModel model);

/// Which pixels-per-normalised-unit turns a normalised-coordinate error into pixels, for
/// thresholds and weights (frontend and estimator option `pixel_scale`).
enum class PixelScale {
  kCentre,     ///< "centre": the focal length at the principal point, for every feature
  kLocal,      ///< "local": the lens's own scale where the feature was seen (pixelScaleAt)
  kWideAngle,  ///< "wide_angle": local for equidistant, double-sphere and extended-unified lenses
};
/// "centre", "local" or "wide_angle"; throws mcvio::InputError naming the key pixel_scale and
/// the value otherwise.
PixelScale pixelScaleFromString(const std::string& name);
/// Whether `scale` asks for the local scale on a lens of this model.
bool usesLocalPixelScale(PixelScale scale, DistortionModel model);

/// Camera with one of the lens models above.
///
/// Pixel convention (OpenCV/EuRoC): pixel (0, 0) is the centre of the top-left pixel, u to the
/// right, v down; the image covers u in [-0.5, width - 0.5) and v in [-0.5, height - 0.5).
/// Camera frame: z along the optical axis, x right, y down.
///
/// Pipeline: p_C -> normalised (x/z, y/z) -> distort -> (fu * xd + cu, fv * yd + cv). For the
/// double sphere, distort((x, y)) = (x, y) / (alpha d2 + (1 - alpha) (xi d1 + 1)) with
/// d1 = |(x, y, 1)|, d2 = |(x, y, xi d1 + 1)|; for the extended unified model
/// (x, y) / (alpha sqrt(beta (x^2 + y^2) + 1) + 1 - alpha): the published projections of p_C,
/// which are the same for every point along a ray.
/// All methods are const and thread-safe.
class CameraModel {
 public:
  using Vec2 = Eigen::Vector2d;
  using Vec3 = Eigen::Vector3d;
  using Vec4 = Eigen::Vector4d;

  /// A 1x1 camera with unit focal length: the value of a calibration not read yet.
  CameraModel() = default;

  /// intrinsics = (fu, fv, cu, cv) [px]; coefficients: 4 values for radial-tangential
  /// (k1 k2 p1 p2) and equidistant (k1 k2 k3 k4), (xi, alpha, 0, 0) for the double sphere,
  /// (alpha, beta, 0, 0) for the extended unified model, ignored for none.
  /// Throws mcvio::InputError on non-positive size or focal length, non-finite values, or
  /// parameters outside a wide-angle model's range (naming the parameter).
  CameraModel(int width, int height, const Vec4& intrinsics, DistortionModel model,
              const Vec4& coefficients = Vec4::Zero());

  /// Projects a point in camera coordinates to a distorted pixel. Returns false if the point is
  /// behind (or on) the camera plane, beyond the valid range of the distortion model, or the
  /// pixel falls outside the image; `pixel` (and `J`) are still written whenever z > 0 so a
  /// caller can use out-of-image projections. J = d pixel / d p_C (2x3) when non-null.
  bool project(const Vec3& p_C, Vec2* pixel, Eigen::Matrix<double, 2, 3>* J = nullptr) const;

  /// Projects without the in-image test: false only behind the camera or beyond the model's
  /// valid range.
  bool projectAnywhere(const Vec3& p_C, Vec2* pixel,
                       Eigen::Matrix<double, 2, 3>* J = nullptr) const;

  /// Normalised undistorted -> normalised distorted coordinates; J = d distorted / d undistorted.
  Vec2 distort(const Vec2& undistorted, Eigen::Matrix2d* J = nullptr) const;

  /// Inverse of distort() by Newton iteration. Returns false when it does not converge to a
  /// residual below 1e-10 (points far outside the lens' field of view).
  bool undistort(const Vec2& distorted, Vec2* undistorted) const;

  /// Pixel -> undistorted normalised coordinates (x/z, y/z). False if undistortion fails.
  bool unproject(const Vec2& pixel, Vec2* normalized) const;

  /// Pixel -> unit bearing vector in camera coordinates (z > 0). False if undistortion fails.
  bool unprojectBearing(const Vec2& pixel, Vec3* bearing) const;

  /// Pixel <-> distorted normalised coordinates (intrinsics only, no distortion).
  Vec2 pixelToDistorted(const Vec2& pixel) const;
  Vec2 distortedToPixel(const Vec2& distorted) const;

  /// True if the pixel lies inside the image shrunk by `border` pixels on every side.
  bool isInImage(const Vec2& pixel, double border = 0.0) const;

  int width() const { return width_; }
  int height() const { return height_; }
  double fu() const { return intrinsics_[0]; }
  double fv() const { return intrinsics_[1]; }
  double cu() const { return intrinsics_[2]; }
  double cv() const { return intrinsics_[3]; }
  /// (fu, fv, cu, cv)
  const Vec4& intrinsics() const { return intrinsics_; }
  DistortionModel distortionModel() const { return model_; }
  /// Four coefficients (zeros for DistortionModel::kNone; the last two zero for the
  /// wide-angle models).
  const Vec4& distortionCoefficients() const { return coefficients_; }
  /// 3x3 pinhole matrix K.
  Eigen::Matrix3d cameraMatrix() const;
  /// Pixels per unit of normalised coordinate at the principal point, what a pixel-noise figure
  /// is divided by to weigh normalised residuals: (fu + fv) / 2, and (fu + fv) / (2 (1 + xi))
  /// for the double sphere, whose rays at the centre spread by 1 / (1 + xi).
  double focalLengthAtCentre() const;
  /// Pixels per unit of normalised coordinate at the undistorted point `normalised`: the square
  /// root of |det d pixel / d normalised|, the geometric mean of the lens's radial and tangential
  /// stretch there (focalLengthAtCentre() at the centre; less towards a wide lens's edge).
  double pixelScaleAt(const Vec2& normalised) const;
  /// d pixel / d normalised at the undistorted point `normalised` (2x2).
  Eigen::Matrix2d pixelJacobianAt(const Vec2& normalised) const;

 private:
  bool inValidRange(const Vec2& undistorted) const;
  // The wide-angle models scale a normalised point by 1 / den(r), r its radius; den and
  // d den / d r.
  void wideAngleDenominator(double r, double* den, double* dden_dr) const;
  bool undistortWideAngle(const Vec2& distorted, Vec2* undistorted) const;

  int width_ = 1;
  int height_ = 1;
  Vec4 intrinsics_{1.0, 1.0, 0.0, 0.0};
  DistortionModel model_ = DistortionModel::kNone;
  Vec4 coefficients_ = Vec4::Zero();
};

}  // namespace mcvio
