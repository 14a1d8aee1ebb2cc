#include "mcvio/core/camera_model.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <random>

#include "mcvio/core/input_error.hpp"

namespace mcvio {
namespace {

// EuRoC V1_01 cam0 (sensor.yaml).
CameraModel eurocCam0() {
  return CameraModel(752, 480, {458.654, 457.296, 367.215, 248.375},
                     DistortionModel::kRadialTangential,
                     {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
}

// A fisheye lens with TUM-VI-like equidistant coefficients.
CameraModel fisheye() {
  return CameraModel(512, 512, {190.978, 190.973, 254.932, 256.897}, DistortionModel::kEquidistant,
                     {0.0034823894, 0.000715034, -0.0020532361, 0.00020293673});
}

CameraModel pinhole() {
  return CameraModel(640, 480, {500.0, 510.0, 320.0, 240.0}, DistortionModel::kNone);
}

// EuRoC's cam0 as a double sphere (Basalt-like values) and as an extended unified model.
CameraModel doubleSphere() {
  return CameraModel(752, 480, {349.7, 348.7, 365.8, 249.3}, DistortionModel::kDoubleSphere, {-0.28, 0.57, 0, 0});
}
CameraModel extendedUnified() {
  return CameraModel(752, 480, {460.1, 459.3, 365.8, 249.3}, DistortionModel::kExtendedUnified, {0.61, 1.12, 0, 0});
}
// A 195-degree lens (TUM-VI-like) as a double sphere: its corners look behind the camera plane.
CameraModel wideDoubleSphere() {
  return CameraModel(512, 512, {158.3, 158.3, 254.9, 256.9}, DistortionModel::kDoubleSphere, {-0.17, 0.59, 0, 0});
}

// The published 3D forms of the two wide-angle projections, written on p_C itself (Usenko et
// al. 2018, eq. 40-41 and 17-18), as a check on the model's normalised-coordinate form.
Eigen::Vector2d doubleSphere3d(const CameraModel& c, const Eigen::Vector3d& p) {
  const double xi = c.distortionCoefficients()[0], a = c.distortionCoefficients()[1];
  const double d1 = p.norm();
  const double k = xi * d1 + p.z();
  const double d2 = std::sqrt(p.x() * p.x() + p.y() * p.y() + k * k);
  const double n = a * d2 + (1 - a) * k;
  return {c.fu() * p.x() / n + c.cu(), c.fv() * p.y() / n + c.cv()};
}
Eigen::Vector2d extendedUnified3d(const CameraModel& c, const Eigen::Vector3d& p) {
  const double a = c.distortionCoefficients()[0], b = c.distortionCoefficients()[1];
  const double d = std::sqrt(b * (p.x() * p.x() + p.y() * p.y()) + p.z() * p.z());
  const double n = a * d + (1 - a) * p.z();
  return {c.fu() * p.x() / n + c.cu(), c.fv() * p.y() / n + c.cv()};
}

std::vector<CameraModel> allModels() {
  return {eurocCam0(), fisheye(), pinhole(), doubleSphere(), extendedUnified(), wideDoubleSphere()};
}

bool isWideAngle(const CameraModel& c) { return isProjectionModel(c.distortionModel()); }

// Angle off the optical axis of the ray through a pixel, by bisection on the 3D projection.
double offAxisDegrees(const CameraModel& c, const Eigen::Vector2d& px) {
  const Eigen::Vector2d d = px - Eigen::Vector2d(c.cu(), c.cv());
  const double target = d.norm();
  const Eigen::Vector2d dir = Eigen::Vector2d(d.x() / c.fu(), d.y() / c.fv()).normalized();
  double lo = 0.0, hi = M_PI;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    const Eigen::Vector3d ray(std::sin(mid) * dir.x(), std::sin(mid) * dir.y(), std::cos(mid));
    const Eigen::Vector2d q = c.distortionModel() == DistortionModel::kDoubleSphere ? doubleSphere3d(c, ray)
                                                                                      : extendedUnified3d(c, ray);
    ((q - Eigen::Vector2d(c.cu(), c.cv())).norm() < target ? lo : hi) = mid;
  }
  return lo * 180.0 / M_PI;
}

TEST(CameraModel, DistortionModelNames) {
  EXPECT_EQ(distortionModelFromString("radial-tangential"), DistortionModel::kRadialTangential);
  EXPECT_EQ(distortionModelFromString("equidistant"), DistortionModel::kEquidistant);
  EXPECT_EQ(distortionModelFromString("none"), DistortionModel::kNone);
  EXPECT_EQ(distortionModelFromString("ds"), DistortionModel::kDoubleSphere);
  EXPECT_EQ(distortionModelFromString("eucm"), DistortionModel::kExtendedUnified);
  EXPECT_EQ(distortionCoefficientCount(DistortionModel::kDoubleSphere), 2);
  for (auto m : {DistortionModel::kNone, DistortionModel::kRadialTangential,
                 DistortionModel::kEquidistant, DistortionModel::kDoubleSphere,
                 DistortionModel::kExtendedUnified}) {
    EXPECT_EQ(distortionModelFromString(toString(m)), m);
  }
  try {
    distortionModelFromString("omni");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("omni"), std::string::npos);
  }
}

TEST(CameraModel, RejectsBadParameters) {
  EXPECT_THROW(CameraModel(0, 480, {1, 1, 0, 0}, DistortionModel::kNone), InputError);
  EXPECT_THROW(CameraModel(752, 480, {-1, 1, 0, 0}, DistortionModel::kNone), InputError);
  EXPECT_THROW(CameraModel(752, 480, {1, 1, NAN, 0}, DistortionModel::kNone), InputError);
  EXPECT_THROW(
      CameraModel(752, 480, {1, 1, 0, 0}, DistortionModel::kEquidistant, {0, INFINITY, 0, 0}),
      InputError);
  const auto message = [](DistortionModel m, Eigen::Vector4d k) {
    try {
      CameraModel(752, 480, {350, 350, 376, 240}, m, k);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(DistortionModel::kDoubleSphere, {-1.0, 0.5, 0, 0}), "double sphere xi = -1 is outside (-1, 1]");
  EXPECT_EQ(message(DistortionModel::kDoubleSphere, {0.1, 1.5, 0, 0}), "double sphere alpha = 1.5 is outside [0, 1]");
  EXPECT_EQ(message(DistortionModel::kExtendedUnified, {-0.1, 1.0, 0, 0}), "extended unified alpha = -0.1 is outside [0, 1]");
  EXPECT_EQ(message(DistortionModel::kExtendedUnified, {0.6, 0.0, 0, 0}), "extended unified beta = 0 is outside (0, inf)");
  EXPECT_EQ(message(DistortionModel::kDoubleSphere, {0.1, 0.5, 7, 8}), "accepted");
  // The unused slots are not kept.
  EXPECT_EQ(CameraModel(752, 480, {350, 350, 376, 240}, DistortionModel::kDoubleSphere, {0.1, 0.5, 7, 8})
                .distortionCoefficients(),
            Eigen::Vector4d(0.1, 0.5, 0, 0));
}

TEST(CameraModel, WideAngleModelsMatchTheirPublishedProjections) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(0.0, 88.0 * M_PI / 180.0), azimuth(-M_PI, M_PI), depth(0.2, 40.0);
  for (const CameraModel& cam : {doubleSphere(), extendedUnified(), wideDoubleSphere()}) {
    for (int i = 0; i < 1000; ++i) {
      const double t = angle(rng), a = azimuth(rng);
      const Eigen::Vector3d p = depth(rng) * Eigen::Vector3d(std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), std::cos(t));
      const Eigen::Vector2d expected =
          cam.distortionModel() == DistortionModel::kDoubleSphere ? doubleSphere3d(cam, p) : extendedUnified3d(cam, p);
      Eigen::Vector2d px;
      ASSERT_TRUE(cam.projectAnywhere(p, &px)) << toString(cam.distortionModel()) << " " << t;
      EXPECT_LT((px - expected).norm(), 1e-9 * (1.0 + expected.norm()));
    }
  }
}

TEST(CameraModel, WideAngleUnprojectionStopsAtNinetyDegrees) {
  // Pixels of the 195-degree lens whose rays point behind the camera plane have no normalised
  // coordinates: unprojection refuses them rather than return a ray in front.
  const CameraModel cam = wideDoubleSphere();
  int behind = 0, in_front = 0;
  for (double v = 0; v < cam.height(); v += 8) {
    for (double u = 0; u < cam.width(); u += 8) {
      const Eigen::Vector2d px(u, v);
      if ((px - Eigen::Vector2d(cam.cu(), cam.cv())).norm() < 1.0) continue;
      const double deg = offAxisDegrees(cam, px);
      Eigen::Vector3d bearing;
      const bool ok = cam.unprojectBearing(px, &bearing);
      if (deg > 90.5) {
        EXPECT_FALSE(ok) << px.transpose() << " " << deg;
        ++behind;
      } else if (deg < 89.5) {
        ASSERT_TRUE(ok) << px.transpose() << " " << deg;
        EXPECT_NEAR(std::acos(bearing.z()) * 180.0 / M_PI, deg, 1e-6);
        ++in_front;
      }
    }
  }
  EXPECT_GT(behind, 100);
  EXPECT_GT(in_front, 2000);
}

TEST(CameraModel, PixelScaleAtIsTheAreaAPixelCovers) {
  // A small square of normalised coordinates around a point, projected: its area in pixels is
  // pixelScaleAt^2 times its own.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> xy(-1.2, 1.2);
  for (const CameraModel& cam : allModels()) {
    for (int i = 0; i < 100; ++i) {
      const Eigen::Vector2d n(xy(rng), xy(rng));
      const double h = 1e-5;
      Eigen::Vector2d o, a, b;
      if (!cam.projectAnywhere(n.homogeneous(), &o)) continue;
      ASSERT_TRUE(cam.projectAnywhere((n + Eigen::Vector2d(h, 0)).homogeneous(), &a));
      ASSERT_TRUE(cam.projectAnywhere((n + Eigen::Vector2d(0, h)).homogeneous(), &b));
      const double area = std::abs((a - o).x() * (b - o).y() - (a - o).y() * (b - o).x()) / (h * h);
      EXPECT_NEAR(cam.pixelScaleAt(n), std::sqrt(area), 1e-3 * std::sqrt(area)) << toString(cam.distortionModel());
      Eigen::Matrix2d numeric;
      numeric << (a - o) / h, (b - o) / h;
      EXPECT_LT((cam.pixelJacobianAt(n) - numeric).norm(), 1e-3 * numeric.norm()) << toString(cam.distortionModel());
    }
  }
  // A wide lens's edge: a 60-degree ray's pixel covers far more of the normalised plane.
  const CameraModel ds = doubleSphere();
  EXPECT_LT(ds.pixelScaleAt({std::tan(60.0 * M_PI / 180.0), 0.0}), 0.45 * ds.pixelScaleAt({0.0, 0.0}));  // 0.38
}

TEST(CameraModel, FocalLengthAtCentreIsTheLocalScale) {
  for (const CameraModel& cam : allModels()) {
    Eigen::Vector2d a, b;
    ASSERT_TRUE(cam.projectAnywhere({1e-4, 0.0, 1.0}, &a));
    ASSERT_TRUE(cam.projectAnywhere({0.0, 1e-4, 1.0}, &b));
    const double measured = 0.5 * ((a.x() - cam.cu()) + (b.y() - cam.cv())) / 1e-4;
    EXPECT_NEAR(cam.focalLengthAtCentre(), measured, 1e-3 * measured) << toString(cam.distortionModel());
  }
  EXPECT_NEAR(doubleSphere().focalLengthAtCentre(), 0.5 * (349.7 + 348.7) / 0.72, 1e-9);
}

TEST(CameraModel, PinholeProjectsExactly) {
  const CameraModel cam = pinhole();
  Eigen::Vector2d px;
  ASSERT_TRUE(cam.project({0.2, -0.1, 2.0}, &px));
  EXPECT_DOUBLE_EQ(px.x(), 500.0 * 0.1 + 320.0);
  EXPECT_DOUBLE_EQ(px.y(), 510.0 * -0.05 + 240.0);
}

TEST(CameraModel, RejectsPointsBehindCameraAndOutsideImage) {
  for (const CameraModel& cam : allModels()) {
    Eigen::Vector2d px;
    EXPECT_FALSE(cam.project({0.0, 0.0, -1.0}, &px));
    EXPECT_FALSE(cam.project({0.1, 0.1, 0.0}, &px));
    EXPECT_FALSE(cam.project({NAN, 0.1, 1.0}, &px));
    // 85 degrees off-axis horizontally: outside each of these images (the 195-degree lens reaches
    // that far only towards its corners).
    EXPECT_FALSE(cam.project({11.43, 0.0, 1.0}, &px));
    EXPECT_TRUE(cam.project({0.0, 0.0, 1.0}, &px));
    EXPECT_NEAR(px.x(), cam.cu(), 1e-12);
    EXPECT_NEAR(px.y(), cam.cv(), 1e-12);
  }
  const CameraModel cam = pinhole();
  Eigen::Vector2d px;
  EXPECT_FALSE(cam.project({1.0, 0.0, 1.0}, &px));  // u = 820 > 640
  EXPECT_TRUE(cam.projectAnywhere({1.0, 0.0, 1.0}, &px));
  EXPECT_NEAR(px.x(), 820.0, 1e-12);
}

TEST(CameraModel, ProjectUnprojectRoundTrip) {
  std::mt19937 rng(42);
  for (const CameraModel& cam : allModels()) {
    std::uniform_real_distribution<double> u(0.0, cam.width() - 1.0), v(0.0, cam.height() - 1.0),
        depth(0.3, 30.0);
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector2d px(u(rng), v(rng));
      Eigen::Vector3d bearing;
      if (cam.distortionModel() == DistortionModel::kEquidistant) {
        // A fisheye image corner can lie beyond 90 degrees off-axis, which has no normalised
        // coordinates: unprojection must refuse it rather than return a wrong ray.
        const double theta_d = cam.pixelToDistorted(px).norm();
        if (theta_d > 1.6) {
          EXPECT_FALSE(cam.unprojectBearing(px, &bearing));
          continue;
        }
        if (theta_d > 1.4) continue;
      }
      if (isWideAngle(cam) && offAxisDegrees(cam, px) > 88.0) continue;
      ASSERT_TRUE(cam.unprojectBearing(px, &bearing))
          << toString(cam.distortionModel()) << " " << px.transpose();
      EXPECT_NEAR(bearing.norm(), 1.0, 1e-12);
      const Eigen::Vector3d p = bearing * depth(rng);
      Eigen::Vector2d back;
      ASSERT_TRUE(cam.project(p, &back));
      EXPECT_LT((back - px).norm(), 1e-8) << toString(cam.distortionModel());
    }
  }
}

TEST(CameraModel, ProjectionJacobianMatchesNumerical) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> xy(-0.6, 0.6), z(0.5, 10.0);
  for (const CameraModel& cam : allModels()) {
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector3d p(xy(rng), xy(rng), z(rng));
      Eigen::Vector2d px;
      Eigen::Matrix<double, 2, 3> J;
      if (!cam.projectAnywhere(p, &px, &J)) continue;
      Eigen::Matrix<double, 2, 3> Jn;
      const double h = 1e-6;
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d dp = Eigen::Vector3d::Zero();
        dp[k] = h;
        Eigen::Vector2d a, b;
        ASSERT_TRUE(cam.projectAnywhere(p + dp, &a));
        ASSERT_TRUE(cam.projectAnywhere(p - dp, &b));
        Jn.col(k) = (a - b) / (2 * h);
      }
      EXPECT_LT((J - Jn).norm(), 1e-5 * (1.0 + Jn.norm()))
          << toString(cam.distortionModel()) << "\n"
          << J << "\n"
          << Jn;
    }
  }
}

TEST(CameraModel, DistortionJacobianMatchesNumerical) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> xy(-0.9, 0.9);
  for (const CameraModel& cam : allModels()) {
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector2d p(xy(rng), xy(rng));
      Eigen::Matrix2d J, Jn;
      cam.distort(p, &J);
      const double h = 1e-7;
      for (int k = 0; k < 2; ++k) {
        Eigen::Vector2d dp = Eigen::Vector2d::Zero();
        dp[k] = h;
        Jn.col(k) = (cam.distort(p + dp) - cam.distort(p - dp)) / (2 * h);
      }
      EXPECT_LT((J - Jn).norm(), 1e-6) << toString(cam.distortionModel());
    }
  }
}

TEST(CameraModel, EquidistantJacobianNearOpticalAxis) {
  const CameraModel cam = fisheye();
  Eigen::Matrix2d J;
  cam.distort({1e-12, -1e-12}, &J);
  EXPECT_LT((J - Eigen::Matrix2d::Identity()).norm(), 1e-9);
}

TEST(CameraModel, UndistortConvergesOnEurocCam0OverWholeImage) {
  // Every pixel of a 4-pixel grid plus the exact corners: undistorting then distorting again
  // must reproduce the distorted coordinates to better than 1e-10.
  const CameraModel cam = eurocCam0();
  double worst = 0.0;
  int count = 0;
  for (double v = -0.5; v <= cam.height() - 0.5; v += 4.0) {
    for (double u = -0.5; u <= cam.width() - 0.5; u += 4.0) {
      const Eigen::Vector2d d = cam.pixelToDistorted({u, v});
      Eigen::Vector2d n;
      ASSERT_TRUE(cam.undistort(d, &n)) << u << " " << v;
      worst = std::max(worst, (cam.distort(n) - d).norm());
      ++count;
    }
  }
  for (const Eigen::Vector2d& corner :
       {Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(751.5, -0.5), Eigen::Vector2d(-0.5, 479.5),
        Eigen::Vector2d(751.5, 479.5)}) {
    Eigen::Vector2d n;
    const Eigen::Vector2d d = cam.pixelToDistorted(corner);
    ASSERT_TRUE(cam.undistort(d, &n));
    worst = std::max(worst, (cam.distort(n) - d).norm());
    // EuRoC's barrel distortion pulls the corners inwards: undistorted lies further out.
    EXPECT_GT(n.norm(), d.norm());
  }
  EXPECT_GT(count, 20000);
  EXPECT_LT(worst, 1e-10);
}

TEST(CameraModel, UndistortRejectsNonFiniteInput) {
  for (const CameraModel& cam : allModels()) {
    Eigen::Vector2d n;
    EXPECT_FALSE(cam.undistort({NAN, 0.0}, &n));
  }
}

TEST(CameraModel, EquidistantUndistortRoundTripAtWideAngles) {
  const CameraModel cam = fisheye();
  for (double deg = 1.0; deg < 85.0; deg += 3.0) {
    const double r = std::tan(deg * M_PI / 180.0);
    const Eigen::Vector2d n(r * std::cos(0.3), r * std::sin(0.3));
    Eigen::Vector2d back;
    ASSERT_TRUE(cam.undistort(cam.distort(n), &back));
    EXPECT_LT((back - n).norm(), 1e-9 * (1.0 + r)) << deg;
  }
}

TEST(CameraModel, CameraMatrix) {
  const Eigen::Matrix3d K = eurocCam0().cameraMatrix();
  EXPECT_DOUBLE_EQ(K(0, 0), 458.654);
  EXPECT_DOUBLE_EQ(K(1, 1), 457.296);
  EXPECT_DOUBLE_EQ(K(0, 2), 367.215);
  EXPECT_DOUBLE_EQ(K(1, 2), 248.375);
  EXPECT_DOUBLE_EQ(K(2, 2), 1.0);
}

}  // namespace
}  // namespace mcvio
