#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "mcvio/evaluation/stamped_pose.hpp"

namespace mcvio::evaluation {

/// A time-ordered sequence of poses (an estimate or ground truth). Times strictly increase; the
/// constructor and append() enforce it so every search below can bisect.
class Trajectory {
 public:
  Trajectory() = default;
  /// Throws std::invalid_argument if the times do not strictly increase. `source` names where
  /// the poses came from (a file) for messages.
  explicit Trajectory(std::vector<StampedPose> poses, std::string source = {});

  /// Appends a pose later than the last one (std::invalid_argument otherwise).
  void append(const StampedPose& pose);

  const std::vector<StampedPose>& poses() const { return poses_; }
  const StampedPose& operator[](std::size_t i) const { return poses_[i]; }
  std::size_t size() const { return poses_.size(); }
  bool empty() const { return poses_.empty(); }
  const std::string& source() const { return source_; }
  void setSource(std::string source) { source_ = std::move(source); }

  Timestamp startTime() const;  ///< first pose time (0 when empty)
  Timestamp endTime() const;    ///< last pose time (0 when empty)
  double durationSeconds() const;
  /// Sum of the distances between consecutive positions [m].
  double pathLength() const;

  /// Pose at time t, linear in position and slerp in rotation between the two poses around t.
  /// Empty if t lies outside the trajectory or the two poses are more than max_gap_s apart
  /// (so a hole in the data is never bridged). A pose at exactly t is returned as is.
  std::optional<StampedPose> interpolate(Timestamp t, double max_gap_s) const;

  /// Index of the pose nearest to t, if it lies within max_difference_s of t.
  std::optional<std::size_t> nearest(Timestamp t, double max_difference_s) const;

  /// Every pose mapped through T (T * pose): a world-frame change, as an alignment produces.
  Trajectory transformed(const Eigen::Isometry3d& T) const;

 private:
  std::vector<StampedPose> poses_;
  std::string source_;
};

}  // namespace mcvio::evaluation
