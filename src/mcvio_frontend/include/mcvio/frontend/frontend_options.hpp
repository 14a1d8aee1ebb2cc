#pragma once
#include <string>

#include "mcvio/core/camera_model.hpp"

namespace YAML {
class Node;
}

namespace mcvio::frontend {

/// Tuning of the stereo KLT frontend. Defaults suit 752x480 EuRoC-like stereo at 20 Hz.
/// YAML keys are the member names; unknown keys are rejected so typos do not pass silently.
struct FrontendOptions {
  // Detection
  int max_features = 200;  ///< tracks kept per frame (left camera)
  /// Share of max_features that tracks labelled inconsistent (moving with something other than
  /// the camera's world) may take. They are tracked on for the backend's conflict detection, but
  /// beyond this share they no longer keep new features out of the static view: an occluder
  /// carried with the camera never leaves the image, and its tracks would hold most of the
  /// budget for as long as it stays. 1: they count like any track.
  double moving_track_budget_share = 1.0;
  int grid_cols = 8;       ///< detection grid columns: each cell gets a share of max_features
  int grid_rows = 6;       ///< detection grid rows
  double min_distance_px = 15.0;    ///< minimum distance between any two tracks [px]
  int fast_threshold = 20;          ///< FAST threshold tried first in a cell
  int fast_min_threshold = 5;       ///< lowered down to this in low-texture cells
  int border_px = 10;               ///< no detections and no tracks closer than this to the edge
  bool subpixel_refinement = true;  ///< cornerSubPix on new detections

  // KLT
  int pyramid_levels = 3;  ///< highest pyramid level (0 = no pyramid)
  /// Levels for KLT runs that start at the expected answer: forward-backward and left-right-left
  /// checks, stereo re-matching from last frame's disparity.
  int check_pyramid_levels = 1;
  /// KLT window side [px], odd. 13 keeps a EuRoC frame under 5 ms; 15-21 match a few more
  /// stereo points at 20-50 % more time (see the benchmark).
  int window_size = 13;
  int klt_max_iterations = 15;      ///< per pyramid level
  double klt_epsilon = 0.03;        ///< KLT stop when the update is below this [px]
  double fb_threshold_px = 0.5;     ///< forward-backward error above this drops a temporal track
  bool use_gyro_prediction = true;  ///< initial flow from integrated gyro rotation
  /// Photometric normalisation before KLT, so gain/exposure changes do not break tracks:
  /// "none"; "global" (whole-image mean/std); "local" (mean/std over blocks of
  /// normalization_block_px, bilinearly blended: also copes with partial saturation and
  /// vignetting).
  std::string exposure_normalization = "local";
  int normalization_block_px = 64;
  long long max_imu_gap_ns = 30'000'000;  ///< larger holes in the IMU stream disable prediction

  // Stereo
  double stereo_fb_threshold_px = 1.0;        ///< left-right-left error limit
  double stereo_epipolar_threshold_px = 2.0;  ///< distance to the epipolar line in cam1
  /// A track matched last frame whose new right point lands this close to the disparity
  /// carried over skips the left-right-left check (0 = always check) [px].
  double stereo_prediction_tolerance_px = 0.5;
  /// Stereo points nearer than this are rejected; the motion check also assumes it as the
  /// nearest depth of a track without a stereo point.
  double min_depth_m = 0.1;
  double max_depth_m = 200.0;  ///< stereo points farther than this are rejected

  // Geometric (motion) check
  double ransac_threshold_px = 1.5;  ///< reprojection / epipolar error for kConsistent
  /// Pixels per normalised unit for the motion check's and the stereo check's thresholds: the
  /// focal length at the centre, or the lens's own scale at the track (centre | local |
  /// wide_angle: local for equidistant, ds and eucm lenses). A 160-degree equidistant lens's
  /// edge pixel spans many centre pixels of normalised plane: with the centre's scale a tenth of
  /// the static tracks there failed the motion check on every frame, a conflict in 93 % of them.
  PixelScale pixel_scale = PixelScale::kWideAngle;
  int ransac_iterations = 100;       ///< hypotheses per frame (stops early when all agree)
  int min_tracks_for_check = 8;      ///< fewer temporal tracks: labels stay kUnknown
  unsigned ransac_seed = 42;         ///< deterministic sampling

  // Re-identification (TrackReidentifier)
  /// A corner detected again after its track was lost (it left the view, or an occluder hid it)
  /// and recognised by its ORB descriptor keeps its old track id, so the backend can tell how far
  /// it drifted meanwhile. Lost tracks are candidates from reidentify_min_age_s after they were
  /// lost (before, the backend may still hold their landmark) to reidentify_max_age_s; a match
  /// needs at most reidentify_max_hamming of 256 bits and reidentify_ratio x the second best.
  /// Off by default: where a texture repeats, the patch cannot tell its copies apart (on the
  /// simulator's office most ids it gave back were a copy's, see the frontend README).
  bool reidentify_lost_tracks = false;
  double reidentify_min_age_s = 3.0;
  double reidentify_max_age_s = 60.0;
  int reidentify_max_hamming = 40;
  double reidentify_ratio = 0.8;

  // Masks, as OpenVINS's mask0 / mask1: an 8-bit image of the camera's size per camera whose
  // white pixels (> 127) hold no feature (a robot's own body, a car's bonnet, a fixed lens hood:
  // parts that move with the camera and would look like a motion conflict). Nothing is detected
  // there, a track that enters one is dropped, and a stereo match that lands in cam1's is refused.
  // Empty = none. A relative path in a YAML file is relative to that file's folder.
  std::string mask0;
  std::string mask1;

  // Visualisation
  int history_length = 20;  ///< past positions kept per track for drawing

  /// Throws mcvio::InputError naming the first invalid key.
  void validate() const;
  /// Reads the keys present in `node` (a map) over the defaults, then validates.
  /// `context` (e.g. a file name) prefixes error messages.
  static FrontendOptions fromYaml(const YAML::Node& node, const std::string& context = "frontend");
  /// Loads a YAML file; the options are the root map or its `frontend` entry. Relative mask
  /// paths are taken relative to the file's folder.
  static FrontendOptions fromFile(const std::string& path);
  /// Makes relative mask paths relative to `dir` (the folder of the file they were read from).
  void resolvePathsFrom(const std::string& dir);
};

}  // namespace mcvio::frontend
