#pragma once
#include "mcvio/conflict/relative_motion.hpp"

namespace mcvio::conflict {

/// Propagated-state detector (dissertation ch. 5, delta_MC): the body motion over the horizon as
/// the IMU predicts it from the estimated state at r, against the motion vision alone supports,
/// normalised by both covariances. The 6-dof chi-square exceeds its threshold when vision moves
/// differently from the inertial body: a conflicting motion or a broken estimate.
class PropagatedStateDetector {
 public:
  struct Result {
    double chi2 = 0;
    Eigen::Matrix<double, 6, 1> error = Eigen::Matrix<double, 6, 1>::Zero();  ///< [dtheta, dt] vision - IMU
    bool fired = false;
  };
  explicit PropagatedStateDetector(double chi2_threshold) : threshold_(chi2_threshold) {}
  Result test(const RelativeMotion& imu, const RelativeMotion& vision) const;
  double threshold() const { return threshold_; }

 private:
  double threshold_;
};

}  // namespace mcvio::conflict
