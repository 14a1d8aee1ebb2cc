#pragma once
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace mcvio::estimator {

/// Finds the translation between two sets of world points of the same static scene without
/// knowing which point is which: the window's landmarks after an IMU-dominated interval (in the
/// frame the IMU drifted into) against the landmarks remembered before it (MapMemory). A frontend
/// gives a corner that comes back after an occlusion a new track id, yet the same corner is
/// triangulated near the same place, offset by the drift. Every pair of points closer than
/// `radius_m` votes for its difference; the true offset collects a vote from each corner seen
/// again, a wrong one only chance coincidences. Accepted when enough current points agree within
/// `tolerance_m` and no distinct offset (a repeated texture one period over) is agreed with
/// nearly as sharply: many points find some remembered one near any offset, but only at the
/// drift do they lie as close as their noise.
class LandmarkRegistration {
 public:
  struct Options {
    double radius_m = 5.0;     ///< largest drift searched for
    /// How far a pair may lie from the offset and still agree; at least radius_m / 2000 (no
    /// answer otherwise: the offset cells are numbered within one word).
    double tolerance_m = 0.08;
    int min_points = 12;       ///< agreeing current points needed
    /// ... and at least this fraction of the current points (a floor: on the feature-level
    /// self-occlusions 62-70 % agree with the drift, 40-50 % with the best chance offset).
    double min_fraction = 0.4;
    /// A distinct offset (further than 3 tolerances and 25 cm) agreed with this sharply,
    /// relative to the best, makes the answer ambiguous.
    double max_ambiguity = 0.6;
  };
  struct Result {
    bool valid = false;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< current minus remembered [m]
    int support = 0;         ///< current points agreeing with the offset
    int runner_up = 0;       ///< current points agreeing with the best distinct offset
    double sharpness = 0;    ///< kernel-weighted agreement with the offset
    double runner_up_sharpness = 0;  ///< ... with the best distinct offset
    /// (current, remembered) for each agreeing current point: its pair closest to the offset.
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  };

  LandmarkRegistration() = default;
  explicit LandmarkRegistration(const Options& options) : options_(options) {}

  Result align(const std::vector<Eigen::Vector3d>& current, const std::vector<Eigen::Vector3d>& remembered) const;

 private:
  Options options_;
};

}  // namespace mcvio::estimator
