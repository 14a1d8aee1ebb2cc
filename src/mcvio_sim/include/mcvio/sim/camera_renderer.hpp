#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mcvio/core/camera_calibration.hpp"
#include "mcvio/sim/scene.hpp"

namespace mcvio::sim {

/// How a pixel's footprint on a textured surface picks what it averages.
enum class TextureFilter : std::uint8_t {
  /// One mip level from the geometric mean of the pixel's ray spacing on the z = 1 plane, times
  /// the depth, over the cosine of the viewing angle. That overstates the footprint's area by
  /// 1 / cos of the ray's angle off the axis (0.37 levels at EuRoC's corners, 1.3 at 80 degrees
  /// of a fisheye) and blurs a grazing footprint along its short axis as much as along its long one.
  kIsotropic = 0,
  /// The pixel's footprint from its exact Jacobian on the surface (an ellipse in texels): the mip
  /// level of its minor axis, up to 8 samples spread along its major axis and averaged, as a
  /// GPU's anisotropic filtering does.
  kAnisotropic = 1,
};

/// "isotropic" or "anisotropic".
const char* toString(TextureFilter filter);
/// Inverse of toString(); throws mcvio::InputError naming `key` and the value otherwise.
TextureFilter textureFilterFromString(const std::string& name, const std::string& key);

/// Photometric settings of one rendered image.
struct RenderSettings {
  double gain = 1.0;             ///< exposure/gain factor applied to the scene radiance
  double noise_sigma = 0.0;      ///< additive pixel noise [grey levels]
  std::uint64_t noise_seed = 0;  ///< per image; the same seed gives the same noise
  bool vignetting = true;        ///< darken towards the corners like a real lens
  /// Lens blur: separable kernel [a, 1 - 2a, a] applied before the noise, so geometric edges are
  /// soft like a real lens's (sigma ~0.6 px at 0.2). 0 turns it off.
  double lens_blur = 0.2;
  /// When set (CV_8UC1, camera size), pixels whose ray hits nothing keep this image's value
  /// untouched instead of the sky: used to overlay objects on real images.
  const cv::Mat* background = nullptr;
  bool want_depth = false;       ///< fill RenderResult::depth
  bool mip_mapping = true;       ///< false samples the finest level only (aliases; for comparison)
  TextureFilter texture_filter = TextureFilter::kIsotropic;
};

/// One rendered image with per-pixel body ids.
struct RenderResult {
  cv::Mat image;     ///< CV_8UC1
  cv::Mat body_ids;  ///< CV_8UC1: index of the scene body seen by each pixel, 255 = none
  cv::Mat depth;     ///< CV_32FC1 z-depth in the camera frame [m], 0 = none (if requested)
  std::vector<int> body_pixels;  ///< pixel count per scene body
};

/// Ray-casting renderer for one calibrated camera. The undistorted ray of every pixel centre is
/// computed once from the camera model, so the image is distorted exactly as the model says.
/// The image is cut in 16x16 tiles; per frame each tile keeps the quads whose projected bounds
/// overlap it, sorted by nearest depth, so a pixel tests only a few quads.
class CameraRenderer {
 public:
  /// threads: how many threads render one image (>= 1).
  CameraRenderer(const CameraCalibration& calibration, int threads = 2);

  /// Renders the scene at time t with the device (IMU/body) at pose T_WB.
  void render(const Scene& scene, Timestamp t, const Eigen::Isometry3d& T_WB,
              const RenderSettings& settings, RenderResult* result) const;

  const CameraCalibration& calibration() const { return calibration_; }

 private:
  struct Tile {
    int x0, y0, x1, y1;
    float nx_min, nx_max, ny_min, ny_max;  // bounds of the tile's normalised rays
  };
  CameraCalibration calibration_;
  int threads_;
  int width_, height_;
  std::vector<float> ray_x_, ray_y_;  // undistorted normalised coordinates per pixel
  std::vector<float> footprint_;      // ray spacing to the next pixel (normalised units)
  // d(x, y)/du and d(x, y)/dv of the normalised ray per pixel: x_u, y_u, x_v, y_v.
  std::vector<std::array<float, 4>> ray_differential_;
  std::vector<float> ray_norm_;       // |(x, y, 1)|
  std::vector<float> vignette_;
  std::vector<std::uint8_t> valid_;   // undistortion converged
  std::vector<Tile> tiles_;
  int tiles_x_ = 0;
};

}  // namespace mcvio::sim
