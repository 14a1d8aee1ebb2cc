#pragma once
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/time.hpp"
#include "mcvio/estimator/estimator_output.hpp"

namespace mcvio::pipeline {

/// A TUM file (`t x y z qx qy qz qw`, t in seconds with all nine decimals of the nanosecond stamp)
/// written pose by pose, as published. If later frames re-estimate earlier poses (the conflict
/// window after an IMU-dominated interval), finish() keeps the published version as
/// NAME_online.tum and rewrites NAME.tum with the final estimate. Throws mcvio::InputError when
/// the file cannot be written.
class RevisableTumFile {
 public:
  using Pose = estimator::EstimatorOutput::PoseRevision;

  /// `what` goes into the header comment (e.g. "pose of imu0 in world"). Removes a NAME_online.tum
  /// an earlier run left there.
  RevisableTumFile(std::string path, std::string what);

  /// Appends a pose; stamps must increase.
  void add(Timestamp t, const Eigen::Vector3d& p, const Eigen::Quaterniond& q);
  /// Replaces the poses with these stamps (others are ignored).
  void revise(const std::vector<Pose>& revisions);
  /// Closes the file; if anything was revised, see above.
  void finish();

  bool revised() const { return revised_; }

 private:
  std::string onlinePath() const;

  std::string path_, what_;
  std::ofstream file_;
  std::vector<Pose> poses_;  ///< as in the file, revisions applied
  bool revised_ = false;
};

}  // namespace mcvio::pipeline
