#include "mcvio/core/stereo_rig_calibration.hpp"

#include <gtest/gtest.h>

namespace mcvio {
namespace {

Eigen::Isometry3d fromRowMajor(const double (&d)[16]) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = d[4 * r + c];
  return Eigen::Isometry3d(m);
}

TEST(StereoRigCalibration, EurocExtrinsicsGiveBaselineAndRelativePose) {
  // T_BS of EuRoC V1_01 cam0 and cam1 (sensor.yaml).
  StereoRigCalibration rig;
  rig.cam0.T_BC = fromRowMajor({0.0148655429818, -0.999880929698, 0.00414029679422,
                                -0.0216401454975, 0.999557249008, 0.0149672133247, 0.025715529948,
                                -0.064676986768, -0.0257744366974, 0.00375618835797, 0.999660727178,
                                0.00981073058949, 0.0, 0.0, 0.0, 1.0});
  rig.cam1.T_BC = fromRowMajor({0.0125552670891, -0.999755099723, 0.0182237714554, -0.0198435579556,
                                0.999598781151, 0.0130119051815, 0.0251588363115, 0.0453689425024,
                                -0.0253898008918, 0.0179005838253, 0.999517347078, 0.00786212447038,
                                0.0, 0.0, 0.0, 1.0});
  // EuRoC's stereo baseline is about 11 cm along cam0's x axis.
  EXPECT_NEAR(rig.baseline(), 0.110, 0.002);
  const Eigen::Isometry3d T = rig.T_C0C1();
  EXPECT_GT(T.translation().x(), 0.109);
  EXPECT_LT(std::abs(T.translation().y()), 0.002);
  EXPECT_LT(std::abs(T.translation().z()), 0.002);
  // A point in cam1 maps through the body frame to the same place as through T_C0C1.
  const Eigen::Vector3d p_C1(0.3, -0.2, 4.0);
  const Eigen::Vector3d via_body = rig.cam0.T_BC.inverse() * (rig.cam1.T_BC * p_C1);
  EXPECT_LT((T * p_C1 - via_body).norm(), 1e-12);
  EXPECT_EQ(&rig.camera(0), &rig.cam0);
  EXPECT_EQ(&rig.camera(1), &rig.cam1);
}

}  // namespace
}  // namespace mcvio
