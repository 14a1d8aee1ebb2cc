#include "synthetic_stereo_scene.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

namespace mcvio::frontend::testing {
namespace {

constexpr int kTile = 1024;
constexpr double kTexel = 0.01;  // metres per texel
constexpr double kPatchHalf = 0.35;

struct Plane {
  int axis;       // normal along world axis
  double offset;  // plane: p[axis] = offset
};
const Plane kPlanes[3] = {{2, 5.0}, {0, -1.0}, {1, -2.5}};
constexpr double kPatchZ = 2.0;

Eigen::Matrix3d rotationBC0() {
  // EuRoC cam0 orientation in the body, re-orthonormalised.
  Eigen::Matrix3d r;
  r << 0.0148655429818, -0.999880929698, 0.00414029679422, 0.999557249008, 0.0149672133247,
      0.025715529948, -0.0257744366974, 0.00375618835797, 0.999660727178;
  return Eigen::Quaterniond(r).normalized().toRotationMatrix();
}

}  // namespace

SyntheticStereoScene::SyntheticStereoScene(const Config& config) : config_(config) {
  calibration_.cam0.name = "cam0";
  calibration_.cam1.name = "cam1";
  calibration_.cam0.model = CameraModel(752, 480, {458.654, 457.296, 367.215, 248.375},
                                        DistortionModel::kRadialTangential,
                                        {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
  calibration_.cam1.model = CameraModel(752, 480, {457.587, 456.134, 379.999, 255.238},
                                        DistortionModel::kRadialTangential,
                                        {-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05});
  calibration_.cam0.T_BC.setIdentity();
  calibration_.cam0.T_BC.linear() = rotationBC0();
  calibration_.cam0.T_BC.translation() = Eigen::Vector3d(-0.0216, -0.0647, 0.0098);
  Eigen::Isometry3d T_C0C1 = Eigen::Isometry3d::Identity();
  T_C0C1.linear() =
      Eigen::AngleAxisd(0.004, Eigen::Vector3d(0.3, 1.0, 0.2).normalized()).toRotationMatrix();
  T_C0C1.translation() = Eigen::Vector3d(0.110, -0.0004, 0.0009);
  calibration_.cam1.T_BC = calibration_.cam0.T_BC * T_C0C1;

  // Multi-scale smooth noise, tiled: corners at several sizes, band-limited for clean sampling.
  std::mt19937 rng(config.seed);
  std::normal_distribution<float> n01(0.f, 1.f);
  texture_ = cv::Mat::zeros(kTile, kTile, CV_32F);
  for (double sigma : {2.0, 5.0, 12.0}) {
    cv::Mat noise(kTile, kTile, CV_32F);
    for (int r = 0; r < kTile; ++r)
      for (int c = 0; c < kTile; ++c) noise.at<float>(r, c) = n01(rng);
    // Blur a wrap-padded copy so the tile stays seamless.
    const int pad = static_cast<int>(4 * sigma);
    cv::Mat padded, blurred;
    cv::copyMakeBorder(noise, padded, pad, pad, pad, pad, cv::BORDER_WRAP);
    cv::GaussianBlur(padded, padded, cv::Size(0, 0), sigma, sigma);
    blurred = padded(cv::Rect(pad, pad, kTile, kTile)).clone();
    cv::Scalar m, s;
    cv::meanStdDev(blurred, m, s);
    texture_ += (blurred - m[0]) / s[0];
  }
  cv::Scalar m, s;
  cv::meanStdDev(texture_, m, s);
  texture_ = (texture_ - m[0]) * (45.0 / s[0]) + 128.0;

  for (int cam = 0; cam < 2; ++cam) {
    const CameraModel& model = calibration_.camera(cam).model;
    rays_[static_cast<std::size_t>(cam)].create(model.height(), model.width(), CV_64FC3);
    for (int v = 0; v < model.height(); ++v) {
      for (int u = 0; u < model.width(); ++u) {
        Eigen::Vector2d n;
        model.unproject(Eigen::Vector2d(u, v), &n);
        rays_[static_cast<std::size_t>(cam)].at<cv::Vec3d>(v, u) = cv::Vec3d(n.x(), n.y(), 1.0);
      }
    }
  }
}

Timestamp SyntheticStereoScene::frameTime(int k) const {
  return 1'000'000'000LL + static_cast<Timestamp>(k) * 50'000'000LL;
}

Eigen::Isometry3d SyntheticStereoScene::T_WB(double t) const {
  const double a = config_.rotation_amplitude_rad;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(a * std::sin(0.9 * t), Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(a * std::sin(0.7 * t + 0.5), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(0.5 * a * std::sin(1.1 * t), Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.05 * std::sin(0.8 * t), config_.camera_speed_mps * t - 0.3,
                                    0.15 * std::sin(0.5 * t));
  return T;
}

Eigen::Isometry3d SyntheticStereoScene::T_WC(int k, int cam) const {
  return T_WB(static_cast<double>(k) / kFrameRateHz) * calibration_.camera(cam).T_BC;
}

Eigen::Vector3d SyntheticStereoScene::patchCenter(double t) const {
  return {-0.1, 0.5 - config_.patch_speed_mps * t, kPatchZ};
}

bool SyntheticStereoScene::castRay(int k, int cam, const Eigen::Vector2d& pixel,
                                   SurfacePoint* hit) const {
  Eigen::Vector2d n;
  if (!calibration_.camera(cam).model.unproject(pixel, &n)) return false;
  const Eigen::Isometry3d T = T_WC(k, cam);
  const Eigen::Vector3d o = T.translation();
  const Eigen::Vector3d d = T.linear() * n.homogeneous();
  double best = 1e9;
  if (config_.moving_patch && std::abs(d.z()) > 1e-9) {
    const double lambda = (kPatchZ - o.z()) / d.z();
    const Eigen::Vector3d p = o + lambda * d;
    const Eigen::Vector3d local = p - patchCenter(static_cast<double>(k) / kFrameRateHz);
    if (lambda > 0 && std::abs(local.x()) < kPatchHalf && std::abs(local.y()) < kPatchHalf) {
      best = lambda;
      hit->surface = 3;
      hit->point = local;
    }
  }
  for (int s = 0; s < 3; ++s) {
    const int ax = kPlanes[s].axis;
    if (std::abs(d[ax]) < 1e-9) continue;
    const double lambda = (kPlanes[s].offset - o[ax]) / d[ax];
    if (lambda > 0 && lambda < best) {
      best = lambda;
      hit->surface = s;
      hit->point = o + lambda * d;
    }
  }
  return best < 1e9;
}

bool SyntheticStereoScene::project(const SurfacePoint& p, int k, int cam,
                                   Eigen::Vector2d* pixel) const {
  Eigen::Vector3d world = p.point;
  if (p.surface == 3) world += patchCenter(static_cast<double>(k) / kFrameRateHz);
  const Eigen::Vector3d pc = T_WC(k, cam).inverse() * world;
  return calibration_.camera(cam).model.projectAnywhere(pc, pixel);
}

double SyntheticStereoScene::shade(int surface, const Eigen::Vector3d& p) const {
  // Texture coordinates: the two in-plane world axes (patch: its own x, y), offset per surface.
  double a = 0, b = 0;
  switch (surface) {
    case 0:
      a = p.x();
      b = p.y();
      break;
    case 1:
      a = p.y() + 3.1;
      b = p.z() + 1.7;
      break;
    case 2:
      a = p.x() + 5.3;
      b = p.z() + 0.9;
      break;
    default:
      a = p.x() + 2.2;
      b = p.y() + 7.7;
      break;
  }
  double u = a / kTexel, v = b / kTexel;
  u -= std::floor(u / kTile) * kTile;
  v -= std::floor(v / kTile) * kTile;
  const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
  const double fu = u - u0, fv = v - v0;
  const int u1 = (u0 + 1) % kTile, v1 = (v0 + 1) % kTile;
  const int uu0 = u0 % kTile, vv0 = v0 % kTile;
  return (1 - fv) * ((1 - fu) * texture_.at<float>(vv0, uu0) + fu * texture_.at<float>(vv0, u1)) +
         fv * ((1 - fu) * texture_.at<float>(v1, uu0) + fu * texture_.at<float>(v1, u1));
}

cv::Mat SyntheticStereoScene::renderImage(int k, int cam) const {
  const CameraModel& model = calibration_.camera(cam).model;
  const Eigen::Isometry3d T = T_WC(k, cam);
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d o = T.translation();
  const Eigen::Vector3d patch = patchCenter(static_cast<double>(k) / kFrameRateHz);
  std::mt19937 rng(config_.seed * 7919u + static_cast<unsigned>(k) * 2u +
                   static_cast<unsigned>(cam));
  std::normal_distribution<double> noise(0.0, config_.noise_sigma);
  std::uniform_real_distribution<double> gain_dist(0.6, 1.4);
  const double gain = config_.random_gain ? gain_dist(rng) : 1.0;
  cv::Mat img(model.height(), model.width(), CV_8UC1);
  const cv::Mat& rays = rays_[static_cast<std::size_t>(cam)];
  for (int v = 0; v < img.rows; ++v) {
    for (int u = 0; u < img.cols; ++u) {
      const cv::Vec3d& r = rays.at<cv::Vec3d>(v, u);
      const Eigen::Vector3d d = R * Eigen::Vector3d(r[0], r[1], r[2]);
      double best = 1e9;
      int surface = -1;
      Eigen::Vector3d point;
      if (config_.moving_patch && std::abs(d.z()) > 1e-9) {
        const double lambda = (kPatchZ - o.z()) / d.z();
        const Eigen::Vector3d local = o + lambda * d - patch;
        if (lambda > 0 && std::abs(local.x()) < kPatchHalf && std::abs(local.y()) < kPatchHalf) {
          best = lambda;
          surface = 3;
          point = local;
        }
      }
      for (int s = 0; s < 3; ++s) {
        const int ax = kPlanes[s].axis;
        if (std::abs(d[ax]) < 1e-9) continue;
        const double lambda = (kPlanes[s].offset - o[ax]) / d[ax];
        if (lambda > 0 && lambda < best) {
          best = lambda;
          surface = s;
          point = o + lambda * d;
        }
      }
      const double value = surface < 0 ? 0.0 : gain * shade(surface, point) + noise(rng);
      img.at<uchar>(v, u) = cv::saturate_cast<uchar>(value);
    }
  }
  return img;
}

StereoInput SyntheticStereoScene::render(int k) const {
  StereoInput in;
  in.t = frameTime(k);
  in.left = renderImage(k, 0);
  in.right = renderImage(k, 1);
  // Body rate from the exact attitude: log(R(t)^T R(t + h)) / h at each 200 Hz sample.
  const Timestamp t_prev = k == 0 ? in.t - 50'000'000LL : frameTime(k - 1);
  for (Timestamp t = t_prev + 5'000'000LL; t <= in.t; t += 5'000'000LL) {
    const double ts = toSeconds(t - frameTime(0));
    const double h = 1e-4;
    const Eigen::Matrix3d dR = T_WB(ts - h).linear().transpose() * T_WB(ts + h).linear();
    const Eigen::AngleAxisd aa(dR);
    ImuSample s;
    s.t = t;
    s.gyro = aa.axis() * aa.angle() / (2 * h);
    in.imu.push_back(s);
  }
  return in;
}

}  // namespace mcvio::frontend::testing
