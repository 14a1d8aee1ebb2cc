#include "mcvio/conflict/propagated_state_detector.hpp"

#include "mcvio/conflict/so3_math.hpp"

namespace mcvio::conflict {

PropagatedStateDetector::Result PropagatedStateDetector::test(const RelativeMotion& imu,
                                                              const RelativeMotion& vision) const {
  Result r;
  r.error.head<3>() = so3::log(imu.R.transpose() * vision.R);
  r.error.tail<3>() = vision.t - imu.t;
  const Eigen::Matrix<double, 6, 6> S = imu.covariance + vision.covariance;
  r.chi2 = r.error.dot(S.ldlt().solve(r.error));
  if (!std::isfinite(r.chi2)) r.chi2 = 0;
  r.fired = r.chi2 > threshold_;
  return r;
}

}  // namespace mcvio::conflict
