#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/time.hpp"

namespace mcvio::evaluation {

/// Pose of the body (imu0) frame B in the world frame W at time t: x_W = q * x_B + p.
struct StampedPose {
  Timestamp t = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();

  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = p;
    return T;
  }
};

}  // namespace mcvio::evaluation
