#pragma once
#include <vector>

#include "mcvio/conflict/relative_motion.hpp"

namespace mcvio::conflict {

/// Vision-only motion between frames r and k: points triangulated by the stereo pair of r,
/// re-observed by cam0 of k (PnP). Gauss-Newton on SO(3) x R^3 with Huber weights and a final
/// inlier re-fit. Independent of the estimator's state, so it is what "vision alone" says.
/// Each point's stereo depth uncertainty at r (TrackedPoint::depth_sigma_r) is projected into
/// frame k and weighs its residual: over a brisk horizon the depth error of a far point moves
/// its reprojection by pixels along the direction of travel.
class RelativePoseSolver {
 public:
  struct Options {
    double observation_sigma_px = 1.0;
    double huber_px = 2.0;
    double outlier_px = 6.0;   ///< residuals above this are excluded from the final fit
    int iterations = 8;
    int min_points = 8;
    bool depth_weighting = true;  ///< weigh by the depth uncertainty (false: pixel noise only)
  };
  struct Result {
    bool valid = false;
    RelativeMotion motion;     ///< covariance over [dtheta, dt] from the Gauss-Newton Hessian
    int inliers = 0;
    double rms_px = 0;
  };

  RelativePoseSolver(const RigGeometry& rig, const Options& options) : rig_(rig), options_(options) {}
  /// @param initial starting guess (the IMU prediction).
  Result solve(const std::vector<TrackedPoint>& points, const RelativeMotion& initial) const;

 private:
  RigGeometry rig_;
  Options options_;
};

}  // namespace mcvio::conflict
