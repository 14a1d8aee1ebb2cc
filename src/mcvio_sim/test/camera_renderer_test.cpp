#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "mcvio/sim/camera_renderer.hpp"
#include "mcvio/sim/euroc_rig_defaults.hpp"

namespace mcvio::sim {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

MipmappedTexture uniformTexture(std::uint8_t value) {
  return MipmappedTexture(16, std::vector<std::uint8_t>(256, value));
}

/// A bright disc on a dark square: its intensity centroid is the projection of its centre.
MipmappedTexture discTexture() {
  const int n = 128;
  std::vector<std::uint8_t> px(n * n, 20);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (std::hypot(x + 0.5 - n / 2.0, y + 0.5 - n / 2.0) < 40.0) px[y * n + x] = 220;
  return MipmappedTexture(n, px);
}

/// A quad of half size `half` centred at `centre_w`, facing the camera with rotation R_WC.
TexturedQuad facingQuad(const Vector3d& centre_w, const Eigen::Matrix3d& R_WC, double half, int texture,
                        double texel) {
  TexturedQuad q;
  q.axis_u = R_WC.col(0);
  q.axis_v = R_WC.col(1);
  q.origin = centre_w - half * q.axis_u - half * q.axis_v;
  q.size_u = q.size_v = 2 * half;
  q.texture = texture;
  q.texel_size = texel;
  q.brightness = 1.0f;
  return q;
}

/// Mean absolute change of the image between the device at the identity and at `moved`.
double meanChange(const CameraRenderer& renderer, const Scene& scene, const RenderSettings& settings,
                  const Eigen::Isometry3d& moved) {
  RenderResult a, b;
  renderer.render(scene, 0, Eigen::Isometry3d::Identity(), settings, &a);
  renderer.render(scene, 0, moved, settings, &b);
  cv::Mat diff;
  cv::absdiff(a.image, b.image, diff);
  return cv::mean(diff)[0];
}

Vector2d intensityCentroid(const cv::Mat& img, int threshold) {
  double sw = 0, su = 0, sv = 0;
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u) {
      const int w = img.at<std::uint8_t>(v, u) - threshold;
      if (w <= 0) continue;
      sw += w;
      su += w * u;
      sv += w * v;
    }
  return sw > 0 ? Vector2d(su / sw, sv / sw) : Vector2d(-1, -1);
}

TEST(CameraRenderer, MarkersAppearWhereTheCalibrationProjectsThemInBothCameras) {
  const StereoRigCalibration rig = eurocRigDefaults();
  CameraRenderer r0(rig.cam0, 2), r1(rig.cam1, 2);
  const Eigen::Isometry3d T_WB = Eigen::Isometry3d::Identity();
  const Eigen::Matrix3d R_WC0 = rig.cam0.T_BC.linear();
  RenderSettings settings;
  settings.vignetting = false;

  // Marker positions in cam0 coordinates: centre, towards the corners (strong distortion), near.
  const Vector3d markers[] = {{0.0, 0.0, 2.0}, {1.1, 0.6, 2.5}, {-1.2, -0.65, 2.4},
                              {0.9, -0.55, 2.0}, {-0.25, 0.2, 0.8}};
  for (const Vector3d& p_c0 : markers) {
    Scene scene;
    const int dark = scene.addTexture(uniformTexture(20));
    const int disc = scene.addTexture(discTexture());
    SceneBody world;
    world.quads.push_back(facingQuad(rig.cam0.T_BC * Vector3d(0, 0, 20), R_WC0, 40.0, dark, 0.05));
    scene.addBody(world);
    SceneBody marker;
    const double half = 0.06 * p_c0.z() / 2.0;
    marker.quads.push_back(facingQuad(rig.cam0.T_BC * p_c0, R_WC0, half, disc, 2 * half / 128));
    scene.addBody(marker);

    RenderResult out0, out1;
    r0.render(scene, 0, T_WB, settings, &out0);
    r1.render(scene, 0, T_WB, settings, &out1);
    Vector2d expect0, expect1;
    ASSERT_TRUE(rig.cam0.model.project(p_c0, &expect0));
    const Vector3d p_c1 = rig.cam1.T_BC.inverse() * (rig.cam0.T_BC * p_c0);
    ASSERT_TRUE(rig.cam1.model.project(p_c1, &expect1));
    const Vector2d got0 = intensityCentroid(out0.image, 25);
    const Vector2d got1 = intensityCentroid(out1.image, 25);
    EXPECT_LT((got0 - expect0).norm(), 0.15) << "cam0 marker at " << p_c0.transpose();
    EXPECT_LT((got1 - expect1).norm(), 0.15) << "cam1 marker at " << p_c0.transpose();
    // Disparity of a point straight ahead is about f * baseline / z.
    const double disparity = got0.x() - got1.x();
    EXPECT_NEAR(disparity, expect0.x() - expect1.x(), 0.2);
    EXPECT_GT(out0.body_pixels[1], 0);
  }
}

TEST(CameraRenderer, DepthBufferPointsReprojectOntoTheirPixels) {
  const StereoRigCalibration rig = eurocRigDefaults();
  for (int cam = 0; cam < 2; ++cam) {
    const CameraCalibration& c = rig.camera(cam);
    CameraRenderer renderer(c, 2);
    Scene scene;
    const int tex = scene.addTexture(MipmappedTexture::generate(TextureStyle::kClutter, 64, 1));
    SceneBody world;
    // A slanted wall 3 m in front of the camera.
    TexturedQuad q;
    const Vector3d u_c = Vector3d(1, 0, 0.4).normalized(), v_c(0, 1, 0);
    q.axis_u = c.T_BC.linear() * u_c;
    q.axis_v = c.T_BC.linear() * v_c;
    q.origin = c.T_BC * (Vector3d(0, 0, 3.0) - 10 * u_c - 10 * v_c);
    q.size_u = q.size_v = 20;
    q.texture = tex;
    world.quads.push_back(q);
    scene.addBody(world);
    RenderSettings settings;
    settings.want_depth = true;
    RenderResult out;
    renderer.render(scene, 0, Eigen::Isometry3d::Identity(), settings, &out);
    const Vector3d n_c = c.T_BC.linear().transpose() * q.normal();
    const Vector3d o_c = c.T_BC.inverse() * q.origin;
    double worst_px = 0, worst_plane = 0;
    for (int v = 3; v < out.depth.rows; v += 37)
      for (int u = 5; u < out.depth.cols; u += 41) {
        const float z = out.depth.at<float>(v, u);
        ASSERT_GT(z, 0.0f);
        Vector2d xy;
        ASSERT_TRUE(c.model.unproject(Vector2d(u, v), &xy));
        const Vector3d p(xy.x() * z, xy.y() * z, z);
        worst_plane = std::max(worst_plane, std::abs(n_c.dot(p - o_c)));
        Vector2d px;
        ASSERT_TRUE(c.model.project(p, &px));
        worst_px = std::max(worst_px, (px - Vector2d(u, v)).norm());
      }
    EXPECT_LT(worst_plane, 1e-4) << "camera " << cam;
    EXPECT_LT(worst_px, 1e-2) << "camera " << cam;
  }
}

TEST(CameraRenderer, AFarFineTextureDoesNotFlickerUnderSubPixelMotion) {
  const StereoRigCalibration rig = eurocRigDefaults();
  CameraRenderer renderer(rig.cam0, 2);
  Scene scene;
  const int tex = scene.addTexture(MipmappedTexture::generate(TextureStyle::kClutter, 512, 3));
  SceneBody world;
  // 1 mm texels 25 m away: ~50 texels per pixel, pure aliasing without mip-mapping.
  const Eigen::Matrix3d R = rig.cam0.T_BC.linear();
  world.quads.push_back(facingQuad(rig.cam0.T_BC * Vector3d(0, 0, 25), R, 40.0, tex, 0.001));
  scene.addBody(world);
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.translation() = R * Vector3d(0.013, 0.007, 0);  // a quarter of a pixel's footprint
  // Mean frame-to-frame change of the static surface under that motion.
  auto flicker = [&](bool mip) {
    RenderSettings settings;
    settings.vignetting = false;
    settings.lens_blur = 0.0;  // judge the texture filtering alone
    settings.mip_mapping = mip;
    return meanChange(renderer, scene, settings, moved);
  };
  const double with_mip = flicker(true), without = flicker(false);
  std::cout << "mean frame-to-frame change: " << with_mip << " with mip-mapping, " << without << " without\n";
  EXPECT_LT(with_mip, 5.0);
  EXPECT_LT(4.0 * with_mip, without) << "mip-mapping must remove most of the aliasing";
}

/// Mean absolute difference to `reference` over the pixels with a hit, within `[theta_lo,
/// theta_hi)` of the optical axis (the camera's own rays).
double meanDifference(const RenderResult& image, const cv::Mat& reference, const CameraModel& model,
                      double theta_lo, double theta_hi) {
  double sum = 0;
  int n = 0;
  for (int v = 0; v < image.image.rows; ++v)
    for (int u = 0; u < image.image.cols; ++u) {
      Vector2d xy;
      if (image.body_ids.at<std::uint8_t>(v, u) == 255 || !model.unproject(Vector2d(u, v), &xy)) continue;
      const double theta = std::atan(xy.norm());
      if (theta < theta_lo || theta >= theta_hi) continue;
      sum += std::abs(image.image.at<std::uint8_t>(v, u) - reference.at<float>(v, u));
      ++n;
    }
  return n > 0 ? sum / n : -1;
}

TEST(CameraRenderer, TheAnisotropicFilterAveragesWhatThePixelCovers) {
  // A 160-degree equidistant lens over a floor and a wall; the truth is each pixel's average
  // over the 8x8 pixels of the same lens at 8 times the resolution.
  constexpr int kW = 96, kH = 64, kSuper = 8;
  const double f = 34.0;
  const CameraModel low(kW, kH, Eigen::Vector4d(f, f, (kW - 1) / 2.0, (kH - 1) / 2.0), DistortionModel::kEquidistant);
  // Pixel U of the fine lens is at low-res (U - 3.5) / 8: its 8x8 block tiles one pixel.
  const double off = (kSuper - 1) / 2.0;
  const CameraModel fine(kW * kSuper, kH * kSuper,
                         Eigen::Vector4d(kSuper * f, kSuper * f, kSuper * (kW - 1) / 2.0 + off, kSuper * (kH - 1) / 2.0 + off),
                         DistortionModel::kEquidistant);
  CameraCalibration c_low, c_fine;
  c_low.model = low;
  c_fine.model = fine;
  Scene scene;
  const int tex = scene.addTexture(MipmappedTexture::generate(TextureStyle::kClutter, 512, 9));
  SceneBody world;
  TexturedQuad floor;  // y = 0.6 below the camera (y down), 12 m deep
  floor.origin = Vector3d(-6, 0.6, 0.05);
  floor.axis_u = Vector3d::UnitX();
  floor.axis_v = Vector3d::UnitZ();
  floor.size_u = floor.size_v = 12.0;
  floor.texture = tex;
  floor.texel_size = 0.004;
  world.quads.push_back(floor);
  TexturedQuad wall = floor;  // 2.5 m ahead
  wall.origin = Vector3d(-6, -6, 2.5);
  wall.axis_v = Vector3d::UnitY();
  wall.size_v = 6.6;
  world.quads.push_back(wall);
  scene.addBody(world);

  RenderSettings settings;
  settings.vignetting = false;
  settings.lens_blur = 0.0;
  // The fine lens filters isotropically, which blurs a little more than the truth: a margin
  // against the anisotropic filter, not for it. Point samples (no mip-mapping) alias even at 64
  // per pixel on the far floor.
  RenderResult truth_fine;
  CameraRenderer(c_fine, 2).render(scene, 0, Eigen::Isometry3d::Identity(), settings, &truth_fine);
  cv::Mat truth;
  cv::Mat(truth_fine.image).convertTo(truth, CV_32F);
  cv::resize(truth, truth, cv::Size(kW, kH), 0, 0, cv::INTER_AREA);

  CameraRenderer renderer(c_low, 2);
  RenderResult iso, aniso;
  settings.texture_filter = TextureFilter::kIsotropic;
  renderer.render(scene, 0, Eigen::Isometry3d::Identity(), settings, &iso);
  settings.texture_filter = TextureFilter::kAnisotropic;
  renderer.render(scene, 0, Eigen::Isometry3d::Identity(), settings, &aniso);
  const double deg = M_PI / 180.0;
  for (const auto& [lo, hi] : {std::pair{0.0, 40.0}, std::pair{40.0, 65.0}, std::pair{65.0, 81.0}}) {
    const double e_iso = meanDifference(iso, truth, low, lo * deg, hi * deg);
    const double e_aniso = meanDifference(aniso, truth, low, lo * deg, hi * deg);
    std::cout << "rays " << lo << "-" << hi << " deg: mean |error| isotropic " << e_iso << ", anisotropic "
              << e_aniso << " grey levels\n";
    ASSERT_GT(e_iso, 0.0);
    EXPECT_LT(e_aniso, e_iso) << lo << "-" << hi << " deg";
  }
  // Sharper, but no aliasing: under a fifth of a pixel's motion the image changes as much as the
  // truth does, far less than without mip-mapping.
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.translation() = Vector3d(0.003, 0.0, 0.004);
  auto flicker = [&](TextureFilter filter, bool mip) {
    settings.texture_filter = filter;
    settings.mip_mapping = mip;
    return meanChange(renderer, scene, settings, moved);
  };
  const double f_iso = flicker(TextureFilter::kIsotropic, true), f_aniso = flicker(TextureFilter::kAnisotropic, true);
  const double f_none = flicker(TextureFilter::kIsotropic, false);
  settings.mip_mapping = true;
  settings.texture_filter = TextureFilter::kIsotropic;
  RenderResult moved_fine;
  CameraRenderer(c_fine, 2).render(scene, 0, moved, settings, &moved_fine);
  cv::Mat truth_moved;
  cv::Mat(moved_fine.image).convertTo(truth_moved, CV_32F);
  cv::resize(truth_moved, truth_moved, cv::Size(kW, kH), 0, 0, cv::INTER_AREA);
  cv::Mat truth_diff;
  cv::absdiff(truth, truth_moved, truth_diff);
  const double f_truth = cv::mean(truth_diff)[0];
  std::cout << "frame-to-frame change: truth " << f_truth << ", isotropic " << f_iso << ", anisotropic " << f_aniso
            << ", no mip-mapping " << f_none << "\n";
  EXPECT_LT(std::abs(f_aniso - f_truth), std::abs(f_iso - f_truth));
  EXPECT_LT(4.0 * f_aniso, f_none);
}

TEST(MipmappedTexture, FarSurfacesSampleCoarseLevelsWithoutAliasing) {
  const MipmappedTexture tex = MipmappedTexture::generate(TextureStyle::kTiles, 256, 2);
  ASSERT_EQ(tex.levels(), 9);
  // At a footprint of 64 texels per pixel the sample is the local average, close to the mean.
  double mean = 0;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) mean += tex.texel(0, x, y);
  mean /= 256.0 * 256.0;
  double spread = 0;
  for (int k = 0; k < 50; ++k) spread = std::max(spread, std::abs(tex.sample(k * 37.3f, k * 11.9f, 8.0f) - mean));
  EXPECT_LT(spread, 1.0);
  // Level 0 keeps the detail: samples vary strongly.
  float lo = 255, hi = 0;
  for (int k = 0; k < 200; ++k) {
    const float s = tex.sample(k * 7.3f, k * 3.1f, 0.0f);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  EXPECT_GT(hi - lo, 60.0f);
}

TEST(MipmappedTexture, EveryStyleBuildsAtEverySizeAndHasCorners) {
  for (int size : {16, 64, 256}) {
    for (int style = 0; style < 4; ++style) {
      const MipmappedTexture tex = MipmappedTexture::generate(static_cast<TextureStyle>(style), size, 5);
      EXPECT_EQ(tex.size(), size);
      if (size < 256) continue;
      // Many sharp steps between neighbouring texels: edges and corners, not smooth gradients.
      int steps = 0;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x + 1 < size; ++x) steps += std::abs(tex.texel(0, x, y) - tex.texel(0, x + 1, y)) > 25;
      EXPECT_GT(steps, size * size / 100) << "style " << style;
    }
  }
  EXPECT_THROW(MipmappedTexture::generate(TextureStyle::kTiles, 100, 1), std::invalid_argument);
}

}  // namespace
}  // namespace mcvio::sim
