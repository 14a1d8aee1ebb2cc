#include "mcvio/estimator/imu_factor.hpp"

namespace mcvio::estimator {

ImuFactor::ImuFactor(const ImuPreintegrator& pre, const Eigen::Vector3d& gravity)
    : dt_(pre.deltaTime()),
      gravity_(gravity),
      delta_q_(pre.deltaQ()),
      delta_v_(pre.deltaV()),
      delta_p_(pre.deltaP()),
      dR_dbg_(pre.dR_dbg()),
      dV_dbg_(pre.dV_dbg()),
      dV_dba_(pre.dV_dba()),
      dP_dbg_(pre.dP_dbg()),
      dP_dba_(pre.dP_dba()),
      bg_lin_(pre.linearizationBias().gyro),
      ba_lin_(pre.linearizationBias().accel),
      sqrt_info_(pre.sqrtInformation()) {}

ceres::CostFunction* ImuFactor::create(const ImuPreintegrator& pre, const Eigen::Vector3d& gravity) {
  return new ceres::AutoDiffCostFunction<ImuFactor, 15, 7, 9, 7, 9>(new ImuFactor(pre, gravity));
}

}  // namespace mcvio::estimator
