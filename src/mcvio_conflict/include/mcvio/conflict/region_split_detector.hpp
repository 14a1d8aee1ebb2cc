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
/// median of x and of y; each side's points give a vision-only motion (RelativePoseSolver) and
/// the 6-dof chi-square between the two sides' motions, which the IMU does not enter, says
/// whether the view holds two motions. The side closer to the IMU prediction is taken as static:
/// its motion, far more precise than the IMU's, can be the reference of a second landmark test.
class RegionSplitDetector {
 public:
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

  /// @param chi2_threshold 6-dof chi-square between the sides' motions above which it fires.
  RegionSplitDetector(const RelativePoseSolver& solver, double chi2_threshold)
      : solver_(solver), compare_(chi2_threshold) {}
  /// @param points tracks with a stereo point at r, seen by cam0 of k; @param imu the IMU
  /// prediction (initial guess of every fit, and the judge of which side is static).
  /// Fewer than 16 points: no cut is tested (each side needs the solver's minimum).
  Result test(const std::vector<TrackedPoint>& points, const RelativeMotion& imu) const;

 private:
  RelativePoseSolver solver_;
  PropagatedStateDetector compare_;
};

}  // namespace mcvio::conflict
