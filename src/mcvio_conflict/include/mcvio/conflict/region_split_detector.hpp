#pragma once
#include <vector>

#include "mcvio/conflict/propagated_state_detector.hpp"
#include "mcvio/conflict/relative_motion.hpp"
#include "mcvio/conflict/relative_pose_solver.hpp"

namespace mcvio::conflict {

/// Region-split detector: two motions in one view. A slow object filling a large part of the
/// image moves each of its tracks too little over the horizon for the per-landmark test, whose
/// IMU prediction is spread by pixels by the estimated velocity and attitude, yet together its
/// tracks bend the vision-only motion. The image of frame k is cut at the quartiles and the
/// median of x and of y; each side's points give a vision-only motion and the 6-dof chi-square
/// between the two sides' motions, which the IMU does not enter, says whether the view holds two
/// motions. The side closer to the IMU prediction is taken as static: its motion, far more precise
/// than the IMU's, can be the reference of a second landmark test.
///
/// Every side is first one Gauss-Newton step of the reprojection error (as RelativePoseSolver's)
/// from a common linearisation point, the vision-only motion of all points: the per-point normal
/// equations are summed once in image order, so the twelve sides cost about one solver iteration
/// instead of twelve solves (the motions of a slow object's side differ from that point by
/// centimetres, well inside the step's linear range). Only in a frame where a cut comes near the
/// threshold are the sides solved robustly.
class RegionSplitDetector {
 public:
  struct Options {
    double chi2_threshold = 60.0;       ///< 6-dof chi-square between the sides' motions
    double observation_sigma_px = 1.0;  ///< floor of the per-side residual scale
    /// Points this far off at the linearisation point are left out (wrong matches). A near object's
    /// tracks can be 20-50 px off the whole view's motion: at 20 px the feature-level slow object
    /// read 0.043 / 0.047 / 0.047 m (seeds 1-3), at 50 px 0.043 / 0.037 / 0.041 m.
    double outlier_px = 50.0;
    int min_points = 8;                 ///< per side
    /// Once the best step's chi-square passes this share of the threshold, every cut is solved
    /// again robustly (RelativePoseSolver), and the best robust cut is the result.
    double refine_fraction = 0.5;
  };
  struct Result {
    bool fired = false;   ///< chi2 above the threshold
    double chi2 = 0;      ///< largest chi-square between the two sides of a cut
    int axis = -1;        ///< cut across normalised x (0) or y (1) of cam0 in frame k; -1: no cut tested
    double cut = 0;       ///< the cut's normalised coordinate
    RelativeMotion static_motion;   ///< vision-only motion of the side closer to the IMU
    RelativeMotion moving_motion;   ///< and of the other side
    double static_chi2_imu = 0;     ///< each side's chi-square against the IMU prediction
    double moving_chi2_imu = 0;
    int static_points = 0;
    int moving_points = 0;
  };

  /// @param solver the robust solver of the sides near the threshold.
  RegionSplitDetector(const RigGeometry& rig, const Options& options, const RelativePoseSolver& solver)
      : rig_(rig), options_(options), compare_(options.chi2_threshold), solver_(solver) {}
  /// @param points tracks with a stereo point at r, seen by cam0 of k; @param imu the IMU
  /// prediction (the judge of which side is static); @param around the linearisation point, the
  /// vision-only motion of all points (or the IMU prediction). Each side needs min_points.
  Result test(const std::vector<TrackedPoint>& points, const RelativeMotion& imu, const RelativeMotion& around) const;

 private:
  RigGeometry rig_;
  Options options_;
  PropagatedStateDetector compare_;
  RelativePoseSolver solver_;
};

}  // namespace mcvio::conflict
