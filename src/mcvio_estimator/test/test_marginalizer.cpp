#include <array>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "mcvio/estimator/anchor_observation_factor.hpp"
#include "mcvio/estimator/imu_factor.hpp"
#include "mcvio/estimator/marginalizer.hpp"
#include "mcvio/estimator/pose_manifold.hpp"
#include "mcvio/estimator/reprojection_factor.hpp"
#include "mcvio/estimator/so3.hpp"

namespace mcvio::estimator {
namespace {

// A small visual-inertial window: 3 frames (pose + speed-bias), IMU factors 0-1 and 1-2, stereo
// landmarks anchored in frames 0 and 1, and a gauge prior on frame 0. All residuals are evaluated
// away from their minimum so gradients are non-zero.
struct SmallProblem {
  std::vector<std::array<double, 7>> poses;
  std::vector<std::array<double, 9>> sbs;
  std::vector<std::array<double, 3>> lms;
  std::vector<int> anchor;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<std::vector<double*>> params;
  std::vector<ImuPreintegrator> pre;
  std::unique_ptr<ceres::LossFunction> loss;
  std::shared_ptr<MarginalizationPrior> gauge;
  Eigen::Isometry3d T_BC0, T_BC1;

  SmallProblem() {
    std::mt19937 rng(7);
    std::normal_distribution<double> nd;
    T_BC0 = Eigen::Isometry3d::Identity();
    T_BC0.linear() = so3::exp(Eigen::Vector3d(-M_PI / 2, 0, 0)) * so3::exp(Eigen::Vector3d(0, M_PI / 2, 0));
    T_BC1 = T_BC0;
    T_BC1.translation() = T_BC0.linear() * Eigen::Vector3d(0.11, 0, 0);
    for (int i = 0; i < 3; ++i) {
      const Eigen::Quaterniond q = so3::expQuat(Eigen::Vector3d(0.02 * i, -0.01 * i, 0.05 * i + 0.01 * nd(rng)));
      poses.push_back({0.1 * i + 0.01 * nd(rng), 0.02 * nd(rng), 0.01 * nd(rng), q.x(), q.y(), q.z(), q.w()});
      sbs.push_back({1.0 + 0.05 * nd(rng), 0.05 * nd(rng), 0.0, 0.001 * nd(rng), 0.001 * nd(rng), 0.001 * nd(rng),
                     0.01 * nd(rng), 0.01 * nd(rng), 0.01 * nd(rng)});
    }
    for (int i = 0; i < 2; ++i) {
      pre.emplace_back(ImuBias{}, ImuNoiseParams{});
      for (int k = 0; k <= 20; ++k) {
        ImuSample s;
        s.t = k * 5'000'000;
        s.gyro = Eigen::Vector3d(0.2, -0.1, 0.5) + 0.01 * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
        s.accel = Eigen::Vector3d(0.3, 0.1, 9.81) + 0.1 * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
        pre.back().integrate(s);
      }
    }
    const Eigen::Vector3d g(0, 0, -9.81);
    for (int i = 0; i < 2; ++i) {
      costs.emplace_back(ImuFactor::create(pre[static_cast<std::size_t>(i)], g));
      params.push_back({poses[i].data(), sbs[i].data(), poses[i + 1].data(), sbs[i + 1].data()});
    }
    const int n_landmarks = 12;
    lms.resize(n_landmarks);
    anchor.resize(n_landmarks);
    const Eigen::Isometry3d T_C1C0 = T_BC1.inverse() * T_BC0;
    for (int l = 0; l < n_landmarks; ++l) {
      anchor[l] = l % 2;
      const Eigen::Vector2d bearing(0.3 * nd(rng), 0.2 * nd(rng));
      lms[l] = {bearing.x() + 0.002 * nd(rng), bearing.y() + 0.002 * nd(rng), 1.0 / (4.0 + nd(rng))};
      costs.emplace_back(new AnchorObservationFactor(bearing, Eigen::Isometry3d::Identity(), 458.0));
      params.push_back({lms[l].data()});
      costs.emplace_back(new AnchorObservationFactor(bearing + Eigen::Vector2d(-0.02, 0.001 * nd(rng)), T_C1C0, 458.0));
      params.push_back({lms[l].data()});
      for (int f = anchor[l] + 1; f < 3; ++f) {
        for (const auto* T : {&T_BC0, &T_BC1}) {
          costs.emplace_back(new ReprojectionFactor(bearing + 0.01 * Eigen::Vector2d(nd(rng), nd(rng)), T_BC0, *T, 458.0));
          params.push_back({poses[anchor[l]].data(), poses[f].data(), lms[l].data()});
        }
      }
    }
    gauge = std::make_shared<MarginalizationPrior>();
    gauge->blocks.push_back({poses[0].data(), BlockKind::kPose, 7, 6, {}});
    gauge->blocks.push_back({sbs[0].data(), BlockKind::kEuclidean, 9, 9, {}});
    for (auto& b : gauge->blocks) b.x_lin.assign(b.data, b.data + b.size);
    gauge->J = 100.0 * Eigen::MatrixXd::Identity(15, 15);
    gauge->r = Eigen::VectorXd::Constant(15, 0.1);
    costs.emplace_back(new MarginalizationFactor(gauge));
    params.push_back({poses[0].data(), sbs[0].data()});
  }

  void addBlocks(ceres::Problem* problem, ceres::Manifold* manifold) {
    for (auto& p : poses) problem->AddParameterBlock(p.data(), 7, manifold);
    for (auto& s : sbs) problem->AddParameterBlock(s.data(), 9);
    for (auto& r : lms) problem->AddParameterBlock(r.data(), 3);
  }
  void registerBlocks(Marginalizer* m) {
    for (auto& p : poses) m->addParameterBlock(p.data(), BlockKind::kPose, 7);
    for (auto& s : sbs) m->addParameterBlock(s.data(), BlockKind::kEuclidean, 9);
    for (auto& r : lms) m->addParameterBlock(r.data(), BlockKind::kLandmark, 3);
  }
  /// Options of a ceres::Problem over this problem's costs and a caller's manifold.
  static ceres::Problem::Options borrowing() {
    ceres::Problem::Options popts;
    popts.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    popts.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return popts;
  }
  /// Every block and every residual.
  std::unique_ptr<ceres::Problem> fullProblem(ceres::Manifold* manifold) {
    auto problem = std::make_unique<ceres::Problem>(borrowing());
    addBlocks(problem.get(), manifold);
    for (std::size_t i = 0; i < costs.size(); ++i) problem->AddResidualBlock(costs[i].get(), nullptr, params[i]);
    return problem;
  }
};

void hessian(ceres::Problem* problem, const std::vector<double*>& order, Eigen::MatrixXd* H, Eigen::VectorXd* g) {
  ceres::Problem::EvaluateOptions opts;
  opts.parameter_blocks = order;
  ceres::CRSMatrix crs;
  std::vector<double> residuals, gradient;
  double cost = 0;
  ASSERT_TRUE(problem->Evaluate(opts, &cost, &residuals, &gradient, &crs));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int k = crs.rows[r]; k < crs.rows[r + 1]; ++k) J(r, crs.cols[k]) = crs.values[k];
  *H = J.transpose() * J;
  *g = Eigen::Map<Eigen::VectorXd>(gradient.data(), static_cast<int>(gradient.size()));
}

// The prior left by marginalising frame 0 (pose, speed-bias) and the landmarks anchored in it,
// plus the residuals that remain, has exactly the information and gradient of the full problem
// marginalised onto the kept states (Schur complement of the full Hessian).
TEST(Marginalizer, PriorEqualsMarginalInformationOfFullProblem) {
  SmallProblem sp;
  PoseManifold manifold;
  std::set<const double*> drop{sp.poses[0].data(), sp.sbs[0].data()};
  for (std::size_t l = 0; l < sp.lms.size(); ++l)
    if (sp.anchor[l] == 0) drop.insert(sp.lms[l].data());

  Marginalizer marg;
  sp.registerBlocks(&marg);
  std::vector<std::size_t> remaining;
  for (std::size_t i = 0; i < sp.costs.size(); ++i) {
    bool touches = false;
    for (double* p : sp.params[i]) touches |= drop.count(p) != 0;
    if (touches)
      marg.addResidualBlock(sp.costs[i].get(), nullptr, sp.params[i]);
    else
      remaining.push_back(i);
  }
  const auto prior = marg.marginalize(drop);
  ASSERT_TRUE(prior);
  EXPECT_FALSE(prior->involves(sp.poses[0].data()));

  const auto full = sp.fullProblem(&manifold);

  std::vector<double*> kept, dropped;
  for (std::size_t i = 1; i < 3; ++i) {
    kept.push_back(sp.poses[i].data());
    kept.push_back(sp.sbs[i].data());
  }
  for (std::size_t l = 0; l < sp.lms.size(); ++l) (sp.anchor[l] == 0 ? dropped : kept).push_back(sp.lms[l].data());
  dropped.push_back(sp.poses[0].data());
  dropped.push_back(sp.sbs[0].data());
  std::vector<double*> order = kept;
  order.insert(order.end(), dropped.begin(), dropped.end());
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  hessian(full.get(), order, &H, &g);
  const int n = 2 * 6 + 2 * 9 + 3 * static_cast<int>(sp.lms.size()) / 2;
  const int m = static_cast<int>(H.rows()) - n;
  const Eigen::MatrixXd Hmm_inv = H.bottomRightCorner(m, m).inverse();
  const Eigen::MatrixXd H_marg = H.topLeftCorner(n, n) - H.topRightCorner(n, m) * Hmm_inv * H.bottomLeftCorner(m, n);
  const Eigen::VectorXd g_marg = g.head(n) - H.topRightCorner(n, m) * Hmm_inv * g.tail(m);
  // Equivalently the inverse of the kept block of the full covariance.
  const Eigen::MatrixXd H_cov = H.inverse().topLeftCorner(n, n).inverse();
  EXPECT_LT((H_marg - H_cov).norm(), 1e-6 * H_marg.norm());

  auto* prior_factor = new MarginalizationFactor(prior);
  ceres::Problem reduced(SmallProblem::borrowing());
  for (double* p : kept) {
    if (p == sp.poses[1].data() || p == sp.poses[2].data())
      reduced.AddParameterBlock(p, 7, &manifold);
    else if (p == sp.sbs[1].data() || p == sp.sbs[2].data())
      reduced.AddParameterBlock(p, 9);
    else
      reduced.AddParameterBlock(p, 3);
  }
  reduced.AddResidualBlock(prior_factor, nullptr, prior_factor->parameterBlocks());
  for (std::size_t i : remaining) reduced.AddResidualBlock(sp.costs[i].get(), nullptr, sp.params[i]);
  Eigen::MatrixXd H_red;
  Eigen::VectorXd g_red;
  hessian(&reduced, kept, &H_red, &g_red);
  EXPECT_LT((H_red - H_marg).norm(), 1e-6 * H_marg.norm()) << "information differs";
  EXPECT_LT((g_red - g_marg).norm(), 1e-6 * std::max(1.0, g_marg.norm())) << "gradient differs";
  // The prior must carry real information (the test can fail).
  EXPECT_GT(prior->information().norm(), 1.0);
  delete prior_factor;
}

// The marginal covariance from the Marginalizer (landmarks eliminated first) equals the block of
// the inverse of the full Hessian.
TEST(Marginalizer, MarginalCovarianceMatchesFullInverse) {
  SmallProblem sp;
  PoseManifold manifold;
  Marginalizer marg;
  sp.registerBlocks(&marg);
  for (std::size_t i = 0; i < sp.costs.size(); ++i) marg.addResidualBlock(sp.costs[i].get(), nullptr, sp.params[i]);
  Eigen::MatrixXd cov;
  ASSERT_TRUE(marg.marginalCovariance(sp.poses[2].data(), &cov));

  const auto full = sp.fullProblem(&manifold);
  std::vector<double*> order{sp.poses[2].data(), sp.poses[0].data(), sp.poses[1].data()};
  for (auto& s : sp.sbs) order.push_back(s.data());
  for (auto& r : sp.lms) order.push_back(r.data());
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  hessian(full.get(), order, &H, &g);
  const Eigen::MatrixXd ref = H.inverse().topLeftCorner(6, 6);
  EXPECT_LT((cov - ref).norm(), 1e-6 * ref.norm());

  // Jointly with frame 2's speed-bias (columns 36-44 of the order above), in the order asked.
  Eigen::MatrixXd joint;
  ASSERT_TRUE(marg.marginalCovariance({sp.sbs[2].data(), sp.poses[2].data()}, &joint));
  ASSERT_EQ(joint.rows(), 15);
  std::vector<int> idx;
  for (int i = 36; i < 45; ++i) idx.push_back(i);
  for (int i = 0; i < 6; ++i) idx.push_back(i);
  const Eigen::MatrixXd Hinv = H.inverse();
  Eigen::MatrixXd joint_ref(15, 15);
  for (int a = 0; a < 15; ++a)
    for (int b = 0; b < 15; ++b) joint_ref(a, b) = Hinv(idx[a], idx[b]);
  EXPECT_LT((joint - joint_ref).norm(), 1e-6 * joint_ref.norm());
  EXPECT_FALSE(marg.marginalCovariance({sp.lms[0].data()}, &joint));  // landmarks are eliminated
}

// Two marginalisations in a row (frame 0, then frame 1, each with the landmarks anchored in it)
// with a gauge prior that knows yaw only weakly: the optimisation's prior is exactly what
// marginalize() gives, and the whole information carried along equals the full problem's on
// frame 2, although the weak yaw is below the optimisation prior's floor.
TEST(Marginalizer, WholeInformationKeepsTheWeakDirectionsForTheCovariance) {
  SmallProblem sp;
  // Yaw sigma 20 rad, and a velocity that does not tell the heading: nothing else knows yaw.
  sp.gauge->J(5, 5) = sp.gauge->J(6, 6) = sp.gauge->J(7, 7) = 0.05;
  PoseManifold manifold;
  auto drop_of = [&](int frame) {
    std::set<const double*> drop{sp.poses[static_cast<std::size_t>(frame)].data(),
                                 sp.sbs[static_cast<std::size_t>(frame)].data()};
    for (std::size_t l = 0; l < sp.lms.size(); ++l)
      if (sp.anchor[l] == frame) drop.insert(sp.lms[l].data());
    return drop;
  };
  std::vector<char> used(sp.costs.size(), 0);
  auto add_touching = [&](Marginalizer* m, const std::set<const double*>& drop) {
    for (std::size_t i = 0; i < sp.costs.size(); ++i) {
      bool touches = false;
      for (double* p : sp.params[i]) touches |= drop.count(p) != 0;
      if (touches && used[i] == 0) {
        m->addResidualBlock(sp.costs[i].get(), nullptr, sp.params[i]);
        used[i] = 1;
      }
    }
  };

  const auto drop0 = drop_of(0);
  Marginalizer m0;
  sp.registerBlocks(&m0);
  add_touching(&m0, drop0);
  const auto split0 = m0.marginalizeSplit(drop0, nullptr, nullptr);
  const auto plain0 = m0.marginalize(drop0);
  ASSERT_TRUE(split0.prior && plain0);
  EXPECT_EQ(split0.prior->J, plain0->J);
  EXPECT_EQ(split0.prior->r, plain0->r);
  ASSERT_TRUE(split0.whole);
  EXPECT_EQ(split0.whole->r.size(), split0.whole->J.rows());
  EXPECT_TRUE(split0.whole->r.isZero());

  const auto drop1 = drop_of(1);
  Marginalizer m1;
  sp.registerBlocks(&m1);
  MarginalizationFactor prior0_factor(split0.prior);
  m1.addResidualBlock(&prior0_factor, nullptr, prior0_factor.parameterBlocks());
  add_touching(&m1, drop1);
  // The whole information of frame 0 stands in for its prior.
  const auto split1 = m1.marginalizeSplit(drop1, split0.whole.get(), &prior0_factor);
  ASSERT_TRUE(split1.prior && split1.whole);
  ASSERT_EQ(split1.prior->blocks.size(), 2u);  // frame 2's pose and speed-bias
  EXPECT_EQ(split1.whole->blocks.size(), split1.prior->blocks.size());
  for (const auto& b : split1.prior->blocks)
    EXPECT_TRUE(b.data == sp.poses[2].data() || b.data == sp.sbs[2].data());

  // Full problem: every residual, frame 2 kept, everything else marginalised.
  const auto full = sp.fullProblem(&manifold);
  std::vector<double*> order{split1.prior->blocks[0].data, split1.prior->blocks[1].data};
  for (double* p : {sp.poses[0].data(), sp.sbs[0].data(), sp.poses[1].data(), sp.sbs[1].data()}) order.push_back(p);
  for (auto& r : sp.lms) order.push_back(r.data());
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  hessian(full.get(), order, &H, &g);
  const int n = 15;
  const Eigen::MatrixXd H_marg = H.inverse().topLeftCorner(n, n).inverse();
  const Eigen::MatrixXd H_split = split1.whole->information();
  EXPECT_LT((H_split - H_marg).norm(), 1e-6 * H_marg.norm()) << "the whole information lost some";
  // The whole information matters: the optimisation's prior alone misses the yaw information, so its
  // yaw variance is far larger than the full problem's (or infinite).
  const Eigen::Matrix<double, n, n> cov_full = H_marg.inverse();
  const Eigen::Matrix<double, n, n> cov_split = H_split.inverse();
  EXPECT_NEAR(cov_split(5, 5), cov_full(5, 5), 1e-3 * cov_full(5, 5));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(split1.prior->information());
  EXPECT_LT(es.eigenvalues().minCoeff(), 1e-6 * es.eigenvalues().maxCoeff());
}

// A residual over an unregistered block is rejected and leaves nothing behind: the covariance is
// exactly the one without it.
TEST(Marginalizer, RejectedResidualLeavesNoTrace) {
  SmallProblem sp;
  std::array<double, 3> unregistered{0.1, 0.2, 0.25};
  Marginalizer with_rejected, clean;
  for (Marginalizer* m : {&with_rejected, &clean}) sp.registerBlocks(m);
  for (std::size_t i = 0; i < sp.costs.size(); ++i) {
    if (i == sp.costs.size() / 2) {
      // The first two blocks are registered: a partial residual must not survive the throw.
      std::size_t visual = 0;
      while (sp.params[visual].size() != 3) ++visual;
      std::vector<double*> bad{sp.params[visual][0], sp.params[visual][1], unregistered.data()};
      EXPECT_THROW(with_rejected.addResidualBlock(sp.costs[visual].get(), nullptr, bad), std::logic_error);
    }
    with_rejected.addResidualBlock(sp.costs[i].get(), nullptr, sp.params[i].data(),
                                   static_cast<int>(sp.params[i].size()));
    clean.addResidualBlock(sp.costs[i].get(), nullptr, sp.params[i]);
  }
  EXPECT_EQ(with_rejected.residualCount(), clean.residualCount());
  Eigen::MatrixXd cov_a, cov_b;
  ASSERT_TRUE(with_rejected.marginalCovariance(sp.poses[2].data(), &cov_a));
  ASSERT_TRUE(clean.marginalCovariance(sp.poses[2].data(), &cov_b));
  EXPECT_EQ(cov_a, cov_b);
}

// A prior over two poses and a speed-bias block; the window's common translation gets a
// covariance of its own.
MarginalizationPrior translationTestPrior(int rows, unsigned seed) {
  MarginalizationPrior prior;
  prior.blocks.push_back({nullptr, BlockKind::kPose, 7, 6, std::vector<double>(7, 0.0)});
  prior.blocks.push_back({nullptr, BlockKind::kEuclidean, 9, 9, std::vector<double>(9, 0.0)});
  prior.blocks.push_back({nullptr, BlockKind::kPose, 7, 6, std::vector<double>(7, 0.0)});
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  prior.J = Eigen::MatrixXd::NullaryExpr(rows, 21, [&]() { return normal(rng); });
  prior.r = Eigen::VectorXd::NullaryExpr(rows, [&]() { return normal(rng); });
  return prior;
}

TEST(MarginalizationPrior, TheCommonTranslationsCovarianceIsReplacedAndTheShapeKept) {
  // Coordinates a common translation leaves unchanged: the first pose's position relative to the
  // last (the anchor, tangent columns 15-17), both attitudes, the speed-bias block.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(18, 21);
  A.block<3, 3>(0, 0).setIdentity();
  A.block<3, 3>(0, 15) = -Eigen::Matrix3d::Identity();
  A.block<3, 3>(3, 3).setIdentity();
  A.block<9, 9>(6, 6).setIdentity();
  A.block<3, 3>(15, 18).setIdentity();
  Eigen::Matrix3d Q;
  Q << 0.09, 0.01, 0.0, 0.01, 0.04, 0.0, 0.0, 0.0, 0.01;
  for (const unsigned seed : {3u, 4u}) {
    MarginalizationPrior prior = translationTestPrior(21, seed);
    const Eigen::MatrixXd L = prior.information();
    prior.setCommonTranslationCovariance(Q);
    ASSERT_EQ(prior.J.rows(), 24);
    const Eigen::MatrixXd cov_after = prior.information().inverse();
    // Where the window is: exactly Q at the anchor, and independent of its shape.
    EXPECT_LT((cov_after.block<3, 3>(15, 15) - Q).norm(), 1e-9) << seed;
    EXPECT_LT((A * cov_after.middleCols(15, 3)).norm(), 1e-9) << seed;
    // Its shape: the marginal covariance of the invariant coordinates, before and after.
    const Eigen::MatrixXd before = A * L.inverse() * A.transpose();
    const Eigen::MatrixXd after = A * cov_after * A.transpose();
    EXPECT_LT((after - before).norm(), 1e-8 * before.norm()) << seed;
  }
  // A bad covariance leaves the prior alone.
  MarginalizationPrior prior = translationTestPrior(21, 5);
  const Eigen::MatrixXd J_before = prior.J;
  prior.setCommonTranslationCovariance(-Q);
  EXPECT_EQ(prior.J, J_before);
}

}  // namespace
}  // namespace mcvio::estimator
