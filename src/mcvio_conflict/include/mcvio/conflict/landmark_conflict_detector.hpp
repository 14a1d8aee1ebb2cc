#pragma once
#include <cstdint>
#include <vector>

#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/conflict/relative_motion.hpp"

namespace mcvio::conflict {

/// Landmark detector (dissertation ch. 5, M_r): each landmark seen by the stereo pair of frame r
/// is moved into frame k by the IMU-predicted motion and compared with where cam0 sees it. The
/// residual is normalised by the predicted pixel covariance (motion, stereo depth and pixel
/// noise). A landmark that disagrees moved in the inertial world. The disagreeing group is then
/// tested for one common rigid motion (RANSAC on the stereo points of frame k): a coherent group is
/// a conflicting body, scattered disagreement is noise.
class LandmarkConflictDetector {
 public:
  struct Verdict {
    std::uint64_t track_id = 0;
    double chi2 = 0;
    bool inconsistent = false;
  };
  struct Result {
    std::vector<Verdict> verdicts;
    int tested = 0;
    int inconsistent = 0;
    double fraction = 0;
    double coherence = 0;      ///< share of the disagreeing group explained by one rigid motion
    int coherent_count = 0;    ///< size of that rigid subgroup
    /// That group's motion in body k: a predicted point P moves to T_group * P.
    Eigen::Isometry3d T_group = Eigen::Isometry3d::Identity();
  };

  LandmarkConflictDetector(const RigGeometry& rig, const ConflictOptions& options) : rig_(rig), options_(options) {}
  Result test(const std::vector<TrackedPoint>& points, const RelativeMotion& imu) const;

 private:
  void fitGroup(const std::vector<TrackedPoint>& points, const RelativeMotion& imu, Result* result) const;
  RigGeometry rig_;
  ConflictOptions options_;
};

}  // namespace mcvio::conflict
