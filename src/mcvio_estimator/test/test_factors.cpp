#include <cmath>
#include <functional>
#include <random>

#include <gtest/gtest.h>

#include "mcvio/estimator/anchor_observation_factor.hpp"
#include "mcvio/estimator/imu_factor.hpp"
#include "mcvio/estimator/marginalization_prior.hpp"
#include "mcvio/estimator/pose_manifold.hpp"
#include "mcvio/estimator/reprojection_factor.hpp"
#include "mcvio/estimator/so3.hpp"
#include "mcvio/estimator/zero_velocity_factor.hpp"

namespace mcvio::estimator {
namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

std::vector<double> makePose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  return {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()};
}

Eigen::Isometry3d makeExtrinsic(const Eigen::Vector3d& rv, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = so3::exp(rv);
  T.translation() = t;
  return T;
}

// Checks a cost function's Jacobians in the tangent space against central differences through
// the manifolds (pose blocks of size 7 use PoseManifold, everything else is Euclidean).
void checkJacobians(const ceres::CostFunction& cost, std::vector<std::vector<double>> params, double tol) {
  const int m = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  std::vector<double*> ptrs;
  for (auto& p : params) ptrs.push_back(p.data());
  std::vector<RowMatrix> J(sizes.size());
  std::vector<double*> jptrs;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    J[i].resize(m, sizes[i]);
    jptrs.push_back(J[i].data());
  }
  Eigen::VectorXd r(m);
  ASSERT_TRUE(cost.Evaluate(ptrs.data(), r.data(), jptrs.data()));
  PoseManifold manifold;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const bool pose = sizes[i] == 7;
    const int tdim = pose ? 6 : sizes[i];
    Eigen::MatrixXd J_t = J[i];
    if (pose) {
      Eigen::Matrix<double, 7, 6, Eigen::RowMajor> P;
      manifold.PlusJacobian(params[i].data(), P.data());
      J_t = J[i] * P;
    }
    const double h = 1e-6;
    for (int k = 0; k < tdim; ++k) {
      std::vector<double> plus = params[i], minus = params[i];
      Eigen::VectorXd d = Eigen::VectorXd::Zero(tdim);
      d[k] = h;
      if (pose) {
        manifold.Plus(params[i].data(), d.data(), plus.data());
        d[k] = -h;
        manifold.Plus(params[i].data(), d.data(), minus.data());
      } else {
        plus[static_cast<std::size_t>(k)] += h;
        minus[static_cast<std::size_t>(k)] -= h;
      }
      Eigen::VectorXd rp(m), rm(m);
      std::vector<double*> pp = ptrs, pm = ptrs;
      pp[i] = plus.data();
      pm[i] = minus.data();
      ASSERT_TRUE(cost.Evaluate(pp.data(), rp.data(), nullptr));
      ASSERT_TRUE(cost.Evaluate(pm.data(), rm.data(), nullptr));
      const Eigen::VectorXd num = (rp - rm) / (2 * h);
      EXPECT_LT((num - J_t.col(k)).norm(), tol * std::max(1.0, num.norm()))
          << "block " << i << " tangent dim " << k << "\nnumeric " << num.transpose() << "\nanalytic "
          << J_t.col(k).transpose();
    }
  }
}

TEST(ReprojectionFactor, JacobiansMatchNumerical) {
  const Eigen::Isometry3d T_BC0 = makeExtrinsic({0.01, -0.02, 1.5}, {0.05, -0.01, 0.02});
  const Eigen::Isometry3d T_BC1 = makeExtrinsic({0.02, -0.01, 1.52}, {0.05, 0.10, 0.01});
  auto pose_a = makePose({0.1, 0.2, 0.3}, so3::expQuat({0.1, -0.2, 0.3}));
  auto pose_t = makePose({0.4, -0.1, 0.35}, so3::expQuat({0.15, -0.1, 0.45}));
  std::vector<double> landmark{0.1, -0.05, 1.0 / 4.0};
  for (const auto* T_BC : {&T_BC0, &T_BC1}) {
    ReprojectionFactor f({0.12, -0.03}, T_BC0, *T_BC, 458.0);
    Eigen::Vector3d p_C;
    ASSERT_TRUE(f.pointInCamera(pose_a.data(), pose_t.data(), landmark.data(), &p_C));
    checkJacobians(f, {pose_a, pose_t, landmark}, 1e-6);
  }
}

// A wide lens's 2x2 whitening: the residual is W times the normalised error, the Jacobians
// follow it, and W = s I gives the scalar path's numbers.
TEST(ReprojectionFactor, TwoByTwoWhiteningWeighsTheNormalisedError) {
  const Eigen::Isometry3d T_BC0 = makeExtrinsic({0.01, -0.02, 1.5}, {0.05, -0.01, 0.02});
  auto pose_a = makePose({0.1, 0.2, 0.3}, so3::expQuat({0.1, -0.2, 0.3}));
  auto pose_t = makePose({0.4, -0.1, 0.35}, so3::expQuat({0.15, -0.1, 0.45}));
  std::vector<double> landmark{0.1, -0.05, 1.0 / 4.0};
  const double* params[] = {pose_a.data(), pose_t.data(), landmark.data()};
  const Eigen::Vector2d measured(0.12, -0.03);
  Eigen::Matrix2d W;
  W << 610.0, -85.0, -85.0, 240.0;  // stretched radially, as at a fisheye's edge
  const ReprojectionFactor wide(measured, T_BC0, T_BC0, W);
  const ReprojectionFactor unit(measured, T_BC0, T_BC0, 1.0);
  Eigen::Vector2d r_wide, r_unit;
  ASSERT_TRUE(wide.Evaluate(params, r_wide.data(), nullptr));
  ASSERT_TRUE(unit.Evaluate(params, r_unit.data(), nullptr));
  EXPECT_GT(r_unit.norm(), 1e-3);
  EXPECT_LT((r_wide - W * r_unit).norm(), 1e-9 * r_wide.norm());
  checkJacobians(wide, {pose_a, pose_t, landmark}, 1e-6);

  const ReprojectionFactor scalar(measured, T_BC0, T_BC0, 458.0);
  const ReprojectionFactor diagonal(measured, T_BC0, T_BC0, Eigen::Matrix2d(458.0 * Eigen::Matrix2d::Identity()));
  Eigen::Vector2d r_s, r_d;
  ASSERT_TRUE(scalar.Evaluate(params, r_s.data(), nullptr));
  ASSERT_TRUE(diagonal.Evaluate(params, r_d.data(), nullptr));
  EXPECT_LT((r_s - r_d).norm(), 1e-9 * r_s.norm());
}

TEST(ReprojectionFactor, ResidualZeroForConsistentGeometry) {
  const Eigen::Isometry3d T_BC0 = makeExtrinsic({0.0, 0.0, 1.57}, {0.0, 0.0, 0.0});
  const Eigen::Vector3d p_W(3.0, 1.0, 0.5);
  const Eigen::Quaterniond q_a = so3::expQuat({0.0, 0.1, 0.2}), q_t = so3::expQuat({0.05, 0.0, 0.3});
  const Eigen::Vector3d p_a(0, 0, 0), p_t(0.3, 0.2, 0.0);
  const Eigen::Isometry3d T_WCa = Eigen::Translation3d(p_a) * q_a * T_BC0;
  const Eigen::Isometry3d T_WCt = Eigen::Translation3d(p_t) * q_t * T_BC0;
  const Eigen::Vector3d ca = T_WCa.inverse() * p_W, ct = T_WCt.inverse() * p_W;
  ReprojectionFactor f(ct.head<2>() / ct.z(), T_BC0, T_BC0, 458.0);
  auto pa = makePose(p_a, q_a), pt = makePose(p_t, q_t);
  double landmark[3] = {ca.x() / ca.z(), ca.y() / ca.z(), 1.0 / ca.z()};
  const double* params[] = {pa.data(), pt.data(), landmark};
  Eigen::Vector2d r;
  ASSERT_TRUE(f.Evaluate(params, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-9);
  landmark[2] *= 1.2;
  ASSERT_TRUE(f.Evaluate(params, r.data(), nullptr));
  EXPECT_GT(r.norm(), 1e-2);
}

TEST(AnchorObservationFactor, JacobianMatchesNumericalAndZeroOnTruth) {
  const Eigen::Isometry3d T_C1C0 = makeExtrinsic({0.001, 0.002, -0.001}, {-0.11, 0.001, 0.0005});
  const Eigen::Vector3d p_C0(0.4, -0.3, 5.0);
  const Eigen::Vector3d p_C1 = T_C1C0 * p_C0;
  std::vector<double> landmark{p_C0.x() / p_C0.z(), p_C0.y() / p_C0.z(), 1.0 / p_C0.z()};
  const double* params[] = {landmark.data()};
  Eigen::Vector2d r;
  AnchorObservationFactor right(p_C1.head<2>() / p_C1.z(), T_C1C0, 458.0);
  AnchorObservationFactor left(p_C0.head<2>() / p_C0.z(), Eigen::Isometry3d::Identity(), 458.0);
  for (const auto* f : {&right, &left}) {
    ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
    EXPECT_LT(r.norm(), 1e-9);
    checkJacobians(*f, {{0.1, -0.05, 0.3}}, 1e-6);
  }
  // Depth is observable through the right camera only.
  std::vector<double> far = landmark;
  far[2] *= 0.5;
  const double* far_params[] = {far.data()};
  ASSERT_TRUE(right.Evaluate(far_params, r.data(), nullptr));
  EXPECT_GT(r.norm(), 1.0);
  ASSERT_TRUE(left.Evaluate(far_params, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-9);
}

TEST(AnchorObservationFactor, TwoByTwoWhiteningWeighsTheNormalisedError) {
  const Eigen::Isometry3d T_C1C0 = makeExtrinsic({0.001, 0.002, -0.001}, {-0.11, 0.001, 0.0005});
  const Eigen::Vector2d measured(0.07, -0.06);
  Eigen::Matrix2d W;
  W << 300.0, 40.0, 40.0, 520.0;
  const AnchorObservationFactor wide(measured, T_C1C0, W), unit(measured, T_C1C0, 1.0);
  std::vector<double> landmark{0.1, -0.05, 0.3};
  const double* params[] = {landmark.data()};
  Eigen::Vector2d r_wide, r_unit;
  ASSERT_TRUE(wide.Evaluate(params, r_wide.data(), nullptr));
  ASSERT_TRUE(unit.Evaluate(params, r_unit.data(), nullptr));
  EXPECT_GT(r_unit.norm(), 1e-3);
  EXPECT_LT((r_wide - W * r_unit).norm(), 1e-9 * r_wide.norm());
  checkJacobians(wide, {landmark}, 1e-6);
}

TEST(ImuFactor, MatchesPreintegratorResidualAndVanishesOnExactData) {
  const Eigen::Vector3d gravity(0, 0, -9.81);
  const Eigen::Vector3d w(0.2, -0.3, 0.5), a_w(0.4, -0.2, 0.3);
  const Eigen::Vector3d p0(1, 2, 3), v0(0.5, -0.1, 0.2);
  const Eigen::Quaterniond q0 = so3::expQuat(Eigen::Vector3d(0.1, 0.2, -0.3));
  ImuBias b;
  b.gyro = Eigen::Vector3d(0.01, 0.02, -0.01);
  b.accel = Eigen::Vector3d(-0.05, 0.1, 0.02);
  ImuPreintegrator pre(ImuBias{}, ImuNoiseParams{});
  for (int k = 0; k <= 20; ++k) {
    const double t = k * 0.005;
    const Eigen::Quaterniond q = q0 * so3::expQuat(w * t);
    ImuSample s;
    s.t = k * 5'000'000;
    s.gyro = w + b.gyro;
    s.accel = q.conjugate() * (a_w - gravity) + b.accel;
    pre.integrate(s);
  }
  pre.repropagate(b);
  const double T = 0.1;
  const Eigen::Quaterniond q1 = q0 * so3::expQuat(w * T);
  const Eigen::Vector3d v1 = v0 + a_w * T, p1 = p0 + v0 * T + 0.5 * a_w * T * T;
  std::unique_ptr<ceres::CostFunction> f(ImuFactor::create(pre, gravity));
  auto pi = makePose(p0, q0), pj = makePose(p1, q1);
  std::vector<double> sbi{v0.x(), v0.y(), v0.z(), b.gyro.x(), b.gyro.y(), b.gyro.z(), b.accel.x(), b.accel.y(), b.accel.z()};
  std::vector<double> sbj{v1.x(), v1.y(), v1.z(), b.gyro.x(), b.gyro.y(), b.gyro.z(), b.accel.x(), b.accel.y(), b.accel.z()};
  const double* params[] = {pi.data(), sbi.data(), pj.data(), sbj.data()};
  Eigen::Matrix<double, 15, 1> r;
  ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-5) << r.transpose();  // whitened: the raw residual is ~1e-12

  // Off the truth the factor equals S * (preintegrator residual).
  ImuBias b2 = b;
  b2.gyro += Eigen::Vector3d(2e-3, -1e-3, 1e-3);
  b2.accel += Eigen::Vector3d(0.02, 0.01, -0.03);
  sbi = {v0.x() + 0.1, v0.y(), v0.z(), b2.gyro.x(), b2.gyro.y(), b2.gyro.z(), b2.accel.x(), b2.accel.y(), b2.accel.z()};
  pj[0] += 0.05;
  ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
  const auto raw = pre.residual(p0, q0, v0 + Eigen::Vector3d(0.1, 0, 0), b2, p1 + Eigen::Vector3d(0.05, 0, 0), q1, v1, b, gravity);
  EXPECT_LT((r - pre.sqrtInformation() * raw).norm(), 1e-6 * r.norm());
  checkJacobians(*f, {pi, sbi, pj, sbj}, 1e-5);

  // Far from the truth in rotation (0.4 rad) and in gyro bias, where the analytic Jacobians'
  // JrInv(residual) and Jr(bias correction) terms differ most from identities.
  const Eigen::Quaterniond q_far = q1 * so3::expQuat(Eigen::Vector3d(0.25, -0.2, 0.25));
  pj = makePose(p1 + Eigen::Vector3d(0.3, -0.1, 0.2), q_far);
  sbi[3] += 0.15;
  sbi[4] -= 0.1;
  sbi[5] += 0.2;
  ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
  EXPECT_GT(r.head<3>().norm(), 1.0);
  checkJacobians(*f, {pi, sbi, pj, sbj}, 1e-5);
}

TEST(ZeroVelocityFactor, Jacobian) {
  ZeroVelocityFactor f(0.01);
  checkJacobians(f, {{0.1, -0.2, 0.3, 0.01, 0.02, 0.03, 0.1, 0.2, 0.3}}, 1e-8);
}

TEST(MarginalizationFactor, ResidualAndJacobianAtLinearizationPoint) {
  auto pose = makePose({1, 2, 3}, so3::expQuat({0.3, -0.2, 0.1}));
  std::vector<double> vec{0.5, -0.5};
  auto prior = std::make_shared<MarginalizationPrior>();
  prior->blocks.push_back({pose.data(), BlockKind::kPose, 7, 6, pose});
  prior->blocks.push_back({vec.data(), BlockKind::kEuclidean, 2, 2, vec});
  std::mt19937 rng(3);
  std::normal_distribution<double> nd;
  prior->J = Eigen::MatrixXd::NullaryExpr(8, 8, [&]() { return nd(rng); });
  prior->r = Eigen::VectorXd::NullaryExpr(8, [&]() { return nd(rng); });
  MarginalizationFactor f(prior);
  EXPECT_LT((prior->evaluate() - prior->r).norm(), 1e-12);
  // At x_lin the tangent Jacobian is exactly J (first-estimate Jacobian).
  checkJacobians(f, {pose, vec}, 1e-6);
}

}  // namespace
}  // namespace mcvio::estimator
