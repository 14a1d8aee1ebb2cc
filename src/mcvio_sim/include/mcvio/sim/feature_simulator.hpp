#pragma once
#include <cstdint>
#include <vector>

#include "mcvio/core/feature_frame.hpp"
#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/dataset/conflict_label.hpp"
#include "mcvio/dataset/ground_truth_state.hpp"
#include "mcvio/sim/simulator_options.hpp"

namespace YAML {
class Node;
}

namespace mcvio::sim {

/// Feature-level simulation settings. YAML keys are the member names.
struct FeatureSimulatorOptions {
  int target_tracks = 150;           ///< tracks kept alive in cam0 per frame
  double mean_track_length = 40.0;   ///< frames; besides leaving the view a track ends at random
  double pixel_noise_sigma = 0.5;    ///< [px] per observation, per axis
  double landmark_density = 20.0;    ///< landmarks per m^2 of surface (at most 60000 per body)
  int min_landmarks_per_body = 1500; ///< small bodies (a laptop, a cabin) get denser points
  int grid_cols = 8, grid_rows = 6;  ///< new tracks go to the emptiest cells of this grid
  double image_border_px = 4.0;      ///< observations closer to the edge are not made
  double max_depth_m = 40.0;
  /// A frontend that re-identifies what it lost: when a landmark whose track ended (it left the
  /// view, went behind an occluder, or KLT lost it) from reidentify_min_age_s to
  /// reidentify_max_age_s before is detected again, it is recognised with this probability and
  /// its track gets the old id back (as mcvio::frontend::TrackReidentifier does); otherwise a
  /// new one. Only the ids depend on it, not the observations. 0: KLT tracking alone.
  double reidentify_probability = 0.0;
  double reidentify_min_age_s = 3.0;
  double reidentify_max_age_s = 60.0;

  static FeatureSimulatorOptions fromYaml(const YAML::Node& node);
  void validate() const;  ///< throws mcvio::InputError naming the key
};

/// Where a track's landmark really is: on which body and where on it.
struct LandmarkTruth {
  int body = 0;                                         ///< index into the scene's bodies
  Eigen::Vector3d p_body = Eigen::Vector3d::Zero();     ///< in the body's own frame
  bool static_in_world = true;                          ///< body 0 style: never moves
};

/// A simulated sequence at feature level, all in memory.
struct FeatureSequence {
  StereoRigCalibration calibration;
  std::vector<FeatureFrame> frames;  ///< stereo observations, camera_index 0 and 1
  std::vector<ImuSample> imu;
  std::vector<dataset::GroundTruthState> ground_truth;
  std::vector<dataset::ConflictLabel> labels;  ///< per frame; fraction of cam0 tracks on conflicting bodies
  std::vector<LandmarkTruth> track_truth;       ///< indexed by track_id
};

/// Generates FeatureFrames straight from ground-truth landmarks on the scenario's surfaces, so
/// the estimator can be tested without the image frontend: tracks live while their landmark is
/// visible (in the image, in front, not occluded) and end at random; new tracks fill the
/// emptiest grid cells; cam1 observes the same track when it sees the landmark. Points on a
/// body that moves in the world at that time are labelled TrackLabel::kInconsistent, others
/// kConsistent. Deterministic for SimulatorOptions::seed.
class FeatureSimulator {
 public:
  FeatureSimulator(SimulatorOptions sim, FeatureSimulatorOptions features);
  FeatureSequence run() const;

 private:
  SimulatorOptions sim_;
  FeatureSimulatorOptions features_;
};

/// Convenience: FeatureSimulator(sim, features).run().
FeatureSequence simulateFeatureSequence(const SimulatorOptions& sim,
                                        const FeatureSimulatorOptions& features = {});

}  // namespace mcvio::sim
