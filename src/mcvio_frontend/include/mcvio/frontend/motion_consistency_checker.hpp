#pragma once
#include <Eigen/Core>
#include <random>
#include <vector>

#include "mcvio/core/feature_frame.hpp"

namespace mcvio::frontend {

/// Finds the dominant camera motion between two frames with RANSAC and labels each temporal
/// track as consistent or inconsistent with it.
///
/// Tracks with a stereo point from the previous frame give a metric test: the camera motion
/// (R, t) is sampled alternately from 2 points with the gyro rotation and from 3 points alone
/// (only the latter without gyro), so the largest consensus wins even if it does not turn like
/// the IMU; it is refined by Gauss-Newton on the inliers, and each point's reprojection error
/// decides its label. This
/// resolves what a two-view epipolar test cannot: an object translating in front of a still
/// camera looks like camera translation to the essential matrix, never to a 3D-2D check.
/// Tracks without depth are judged by their distance to the part of the epipolar line of that
/// motion that a point at least `min_depth_m` in front of the camera can reach.
/// With fewer than `min_tracks` stereo points the check falls back to a 2-point rotation-aided
/// epipolar RANSAC (gyro given) or a 5-point essential-matrix RANSAC.
class MotionConsistencyChecker {
 public:
  /// One track seen in the previous and current left image.
  struct Correspondence {
    Eigen::Vector2d prev_normalized{0, 0};  ///< undistorted, previous frame
    Eigen::Vector2d cur_normalized{0, 0};   ///< undistorted, current frame
    bool has_point = false;                 ///< stereo point available in the previous frame
    Eigen::Vector3d point_prev{0, 0, 1};    ///< that point in previous camera coordinates [m]
    /// d pixel / d normalised at cur_normalized, over the checker's focal_px; zero: the identity
    /// (every track judged by the centre's scale). A wide lens's edge stretches a normalised
    /// error unevenly: radially far less than across.
    Eigen::Matrix2d to_centre = Eigen::Matrix2d::Zero();
  };

  struct Result {
    bool valid = false;   ///< false: too few tracks, labels are kUnknown
    bool metric = false;  ///< the 3D-2D test ran (translation has metric scale)
    Eigen::Matrix3d R_cur_prev = Eigen::Matrix3d::Identity();
    /// Metric: translation [m]. Otherwise a unit direction, up to sign (or zero: pure rotation).
    Eigen::Vector3d t_cur_prev = Eigen::Vector3d::Zero();
    std::vector<TrackLabel> labels;
    std::vector<double> residual_px;  ///< per correspondence, the error that decided its label
    int inliers = 0;
  };

  /// @param threshold_px error limit for kConsistent [px]; @param focal_px converts to
  /// normalised units; @param min_tracks fewer correspondences give an invalid result;
  /// @param min_depth_m nearest depth a track without a stereo point may have (metric test).
  MotionConsistencyChecker(double threshold_px, double focal_px, int iterations, int min_tracks,
                           unsigned seed, double min_depth_m = 0.1);

  /// @param R_cur_prev_prior camera rotation from the gyro, or nullptr.
  Result check(const std::vector<Correspondence>& tracks, const Eigen::Matrix3d* R_cur_prev_prior);

 private:
  Result checkMetric(const std::vector<Correspondence>& tracks, const std::vector<int>& with_point,
                     const Eigen::Matrix3d* prior);
  Result checkEpipolar(const std::vector<Correspondence>& tracks, const Eigen::Matrix3d* prior);
  void labelAll(const std::vector<Correspondence>& tracks, Result* r) const;
  static const Eigen::Matrix2d* toCentre(const Correspondence& tr) {
    return tr.to_centre.isZero(0.0) ? nullptr : &tr.to_centre;
  }

  double threshold_;  // normalised units
  double focal_px_;
  int iterations_;
  int min_tracks_;
  double min_depth_m_;
  std::mt19937 rng_;
};

}  // namespace mcvio::frontend
