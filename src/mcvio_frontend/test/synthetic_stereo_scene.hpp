#pragma once
#include <Eigen/Geometry>
#include <array>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/frontend/stereo_input.hpp"

namespace mcvio::frontend::testing {

/// A ray-cast stereo world for frontend tests with exact ground truth: three textured planes
/// (wall, floor, side wall) and optionally a textured square that moves on its own. Rendered
/// through the same distorted EuRoC-like rig the tracker is given, 752x480 at 20 Hz, with
/// 200 Hz gyro samples of the body motion.
class SyntheticStereoScene {
 public:
  struct Config {
    bool moving_patch = false;
    double patch_speed_mps = 0.4;   ///< patch velocity along world -y [m/s]
    double camera_speed_mps = 0.2;  ///< body drift along world +y [m/s]
    double rotation_amplitude_rad = 0.05;
    double noise_sigma = 1.0;  ///< image noise [grey levels]
    bool random_gain = false;  ///< independent gain in [0.6, 1.4] per frame and camera
    unsigned seed = 7;
  };

  /// Where a pixel's ray lands: surface 0..2 = static planes (world point), 3 = the patch
  /// (point in patch coordinates).
  struct SurfacePoint {
    int surface = -1;
    Eigen::Vector3d point{0, 0, 0};
  };

  explicit SyntheticStereoScene(const Config& config);

  const StereoRigCalibration& calibration() const { return calibration_; }
  static constexpr double kFrameRateHz = 20.0;
  Timestamp frameTime(int k) const;
  Eigen::Isometry3d T_WB(double t_s) const;
  /// Images of frame k with gyro samples in (t_{k-1}, t_k].
  StereoInput render(int k) const;

  bool castRay(int k, int cam, const Eigen::Vector2d& pixel, SurfacePoint* hit) const;
  bool project(const SurfacePoint& p, int k, int cam, Eigen::Vector2d* pixel) const;

 private:
  Eigen::Isometry3d T_WC(int k, int cam) const;
  Eigen::Vector3d patchCenter(double t_s) const;
  double shade(int surface, const Eigen::Vector3d& p) const;
  cv::Mat renderImage(int k, int cam) const;

  Config config_;
  StereoRigCalibration calibration_;
  cv::Mat texture_;              // CV_32F tile
  std::array<cv::Mat, 2> rays_;  // CV_64FC3 undistorted rays per pixel
};

}  // namespace mcvio::frontend::testing
