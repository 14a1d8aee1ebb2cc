#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/dataset/conflict_label.hpp"
#include "mcvio/sim/camera_renderer.hpp"

namespace YAML {
class Node;
}

namespace mcvio::sim {

/// `mcvio inject` settings: an artificial textured plane moving with its own motion in front of
/// the cameras of a recorded EuRoC sequence (the dissertation's EuRoC experiment). The plane's
/// pose is given in cam0 coordinates: it stays at `depth_m` in front of the rig and moves by
/// `velocity_mps` plus a sinusoidal sway, independently of the true device motion, so it
/// conflicts with the IMU. YAML keys are the member names.
struct InjectOptions {
  std::string input_dir;   ///< EuRoC folder (holding mav0/ or mav0 itself)
  std::string output_dir;  ///< written as a complete EuRoC folder plus conflict_labels.csv
  bool overwrite = false;
  double onset_s = 1.0;     ///< seconds after the first stereo frame
  double duration_s = 3.0;  ///< how long the plane is visible [s]
  double depth_m = 1.2;     ///< distance in front of cam0
  double width_m = 1.0;     ///< plane size
  double height_m = 0.7;
  Eigen::Vector2d center_m{0.0, 0.0};                    ///< cam0 x (right), y (down) at onset
  Eigen::Vector3d velocity_mps{0.25, 0.05, 0.0};        ///< constant drift in cam0 coordinates
  double sway_amplitude_m = 0.1;  ///< sinusoidal sideways sway
  double sway_hz = 0.5;
  double spin_rate = 0.1;         ///< rotation about the optical axis [rad/s]
  double texel_size_m = 0.0015;   ///< texture resolution on the plane
  double pixel_noise_sigma = 1.5; ///< noise on the overlay's pixels, like the camera's
  std::uint64_t seed = 1;         ///< texture
  std::string motion_name = "injected_image";
  int threads = 2;
  int png_compression = 0;  ///< zlib level of the written PNGs; 0 as EuRoC (fastest to decode)

  static InjectOptions fromYaml(const YAML::Node& node);
  static InjectOptions fromYamlFile(const std::string& path);
  void validate() const;  ///< throws mcvio::InputError naming the key
};

/// What `mcvio inject` wrote.
struct InjectSummary {
  std::size_t frames = 0;
  std::size_t injected_frames = 0;  ///< frames where the plane covers some of cam0
  std::size_t warnings = 0;         ///< rows of the input the reader skipped
};

/// Draws the moving plane into stereo pairs, consistently in both cameras (each camera ray-casts
/// the same plane through its own calibration, so disparity matches the plane's depth).
class ImageInjector {
 public:
  ImageInjector(InjectOptions options, const StereoRigCalibration& calibration);

  /// Overlays the plane at `since_first_frame` into cam0/cam1 (CV_8UC1, modified in place when
  /// the plane is visible) and returns cam0's label at time t.
  dataset::ConflictLabel overlay(Timestamp t, Timestamp since_first_frame, cv::Mat& cam0,
                                 cv::Mat& cam1) const;
  /// Pose of the plane's frame in cam0 coordinates, seconds after onset.
  Eigen::Isometry3d planeInCam0(double seconds_after_onset) const;

 private:
  InjectOptions options_;
  StereoRigCalibration calibration_;
  Scene scene_;
  std::unique_ptr<CameraRenderer> renderer_[2];
};

/// The `mcvio inject` entry point: reads options.input_dir, writes options.output_dir.
/// progress(done, total) is called per frame. Throws mcvio::InputError for bad input.
InjectSummary runInjection(const InjectOptions& options,
                           const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace mcvio::sim
