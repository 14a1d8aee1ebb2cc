#include "mcvio/sim/euroc_rig_defaults.hpp"

namespace mcvio::sim {
namespace {

Eigen::Isometry3d fromRows(const double (&m)[12]) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) T(r, c) = m[r * 4 + c];
  Eigen::Isometry3d iso;
  iso.matrix() = T;
  // Re-orthonormalise the printed rotation so products of extrinsics stay rigid.
  iso.linear() = Eigen::Quaterniond(T.block<3, 3>(0, 0)).normalized().toRotationMatrix();
  return iso;
}

}  // namespace

StereoRigCalibration eurocRigDefaults() {
  StereoRigCalibration rig;
  rig.cam0.name = "cam0";
  rig.cam0.model = CameraModel(752, 480, {458.654, 457.296, 367.215, 248.375},
                               DistortionModel::kRadialTangential,
                               {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
  rig.cam0.rate_hz = 20.0;
  rig.cam0.T_BC = fromRows({0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
                            0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,
                            -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949});
  rig.cam1.name = "cam1";
  rig.cam1.model = CameraModel(752, 480, {457.587, 456.134, 379.999, 255.238},
                               DistortionModel::kRadialTangential,
                               {-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05});
  rig.cam1.rate_hz = 20.0;
  rig.cam1.T_BC = fromRows({0.0125552670891, -0.999755099723, 0.0182237714554, -0.0198435579556,
                            0.999598781151, 0.0130119051815, 0.0251588363115, 0.0453689425024,
                            -0.0253898008918, 0.0179005838253, 0.999517347078, 0.00786212447038});
  rig.imu.name = "imu0";  // ImuNoiseParams defaults are the ADIS16448 values
  return rig;
}

}  // namespace mcvio::sim
