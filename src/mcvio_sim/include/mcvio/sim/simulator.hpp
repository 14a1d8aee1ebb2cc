#pragma once
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include <opencv2/core.hpp>

#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/dataset/conflict_label.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"
#include "mcvio/sim/camera_renderer.hpp"
#include "mcvio/sim/simulated_world.hpp"
#include "mcvio/sim/simulator_options.hpp"

namespace mcvio::sim {

/// One rendered stereo frame with its conflict label.
struct StereoRender {
  Timestamp t = 0;
  cv::Mat cam0, cam1;  ///< CV_8UC1
  cv::Mat cam0_body_ids;  ///< per-pixel scene body of cam0 (255 = sky)
  dataset::ConflictLabel label;
};

/// What a run wrote and how long it took.
struct SimulationSummary {
  std::size_t frames = 0;
  std::size_t imu_samples = 0;
  std::size_t ground_truth_rows = 0;
  std::size_t conflict_frames = 0;
  double render_seconds = 0;  ///< wall time spent rendering
  double total_seconds = 0;   ///< wall time of writeDataset()
};

/// Simulates a stereo-inertial EuRoC sequence: builds the scenario's world around a synthetic
/// (or, in semi-real mode, recorded) trajectory, synthesises (or keeps and augments) the IMU,
/// and renders the stereo images with per-frame conflict labels. Everything is deterministic
/// for SimulatorOptions::seed.
///
///   auto options = mcvio::sim::SimulatorOptions::fromYamlFile("sim.yaml");
///   mcvio::sim::Simulator sim(options);
///   sim.writeDataset();  // options.output_dir/mav0/...
class Simulator {
 public:
  /// Validates the options, loads calibration and recordings, builds the world, IMU and ground
  /// truth. Throws mcvio::InputError for bad options or input files.
  explicit Simulator(SimulatorOptions options);

  const SimulatorOptions& options() const { return options_; }
  const StereoRigCalibration& calibration() const { return rig_; }
  const SimulatedWorld& world() const { return world_; }
  const std::vector<ImuSample>& imu() const { return imu_; }
  const std::vector<dataset::GroundTruthState>& groundTruth() const { return ground_truth_; }
  const std::vector<Timestamp>& frameTimes() const { return frame_times_; }

  /// Device (IMU/body) pose in the world at time t, as rendered.
  Eigen::Isometry3d bodyPose(Timestamp t) const;
  /// Renders stereo frame `index` (of frameTimes()).
  StereoRender renderFrame(std::size_t index) const;
  /// Renders one camera (0 or 1) of frame `index`, with body ids: what renderFrame() does per
  /// camera, for callers that need only one image or only the label (labelFor(t, cam0)).
  RenderResult renderCamera(std::size_t index, int camera) const;
  /// Conflict label of a cam0 rendering: fraction of pixels on bodies moving in the world.
  dataset::ConflictLabel labelFor(Timestamp t, const RenderResult& cam0) const;

  /// Writes options().output_dir as a EuRoC folder: cam0/cam1 PNGs, imu0, ground truth,
  /// sensor.yaml files and conflict_labels.csv. Rendering and PNG encoding overlap.
  /// progress(done, total) is called after each frame is written, from the writer thread; an
  /// exception it throws stops the run and is rethrown here.
  SimulationSummary writeDataset(const std::function<void(std::size_t, std::size_t)>& progress = {});

 private:
  SimulatorOptions options_;
  StereoRigCalibration rig_;
  SimulatedWorld world_;
  std::vector<ImuSample> imu_;
  std::vector<dataset::GroundTruthState> ground_truth_;
  std::vector<Timestamp> frame_times_;
  // Built on first use: feature-level simulation never renders.
  const CameraRenderer& renderer(int camera) const;
  mutable std::once_flag renderers_built_;
  mutable std::unique_ptr<CameraRenderer> renderer_[2];
};

/// The `mcvio sim` entry point: Simulator(options).writeDataset().
SimulationSummary runSimulation(const SimulatorOptions& options,
                                const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace mcvio::sim
