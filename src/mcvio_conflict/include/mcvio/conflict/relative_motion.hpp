#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mcvio::conflict {

/// Motion of the body between a reference frame r and the current frame k: a point X_k in body k
/// is X_r = R * X_k + t in body r. Covariance over the perturbation [dtheta, dt] with
/// R = R_hat * Exp(dtheta) and t = t_hat + dt.
struct RelativeMotion {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();

  /// A point of body r expressed in body k.
  Eigen::Vector3d toCurrent(const Eigen::Vector3d& X_r) const { return R.transpose() * (X_r - t); }
};

/// Stereo rig geometry the detectors need: camera -> body extrinsics and the focal length that
/// turns normalised coordinates into pixels.
struct RigGeometry {
  Eigen::Isometry3d T_BC0 = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_BC1 = Eigen::Isometry3d::Identity();
  double focal_px = 450.0;
  /// Stereo baseline [m]; |t_C0C1|.
  double baseline() const { return (T_BC0.inverse() * T_BC1).translation().norm(); }
};

/// One landmark as the detectors see it: its point in body r (from the stereo pair of frame r),
/// the depth-along-ray uncertainty of that point, and its observations in frame k.
struct TrackedPoint {
  std::uint64_t track_id = 0;
  Eigen::Vector3d X_r = Eigen::Vector3d::Zero();
  double depth_r = 1.0;        ///< depth in cam0 of frame r [m]
  Eigen::Vector3d ray_r = Eigen::Vector3d::UnitZ();  ///< unit viewing ray of cam0 at r, in body r
  double depth_sigma_r = 0.0;  ///< stereo depth uncertainty along the ray [m]
  Eigen::Vector2d n0_k = Eigen::Vector2d::Zero();    ///< normalised cam0 observation in frame k
  bool has_X_k = false;        ///< frame k also has a stereo point
  Eigen::Vector3d X_k = Eigen::Vector3d::Zero();     ///< that point in body k
  double depth_sigma_k = 0.0;
};

}  // namespace mcvio::conflict
