// Per-frame cost of the conflict detectors on a typical frame: 150 stereo landmarks 2-8 m ahead,
// a third of them (scattered, or the right third of the view) moved 5 cm sideways. Each detector
// runs once per frame; the region split solves its sides robustly only when one side moves.
//   install/mcvio_conflict/lib/mcvio_conflict/bench_conflict_detectors
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/conflict/landmark_conflict_detector.hpp"
#include "mcvio/conflict/region_split_detector.hpp"
#include "mcvio/conflict/relative_pose_solver.hpp"
#include "mcvio/conflict/so3_math.hpp"

namespace {

using namespace mcvio::conflict;

struct Frame {
  RigGeometry rig;
  RelativeMotion imu;
  std::vector<TrackedPoint> points;
};

Frame makeFrame(bool object_on_one_side) {
  Frame f;
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // cam0 looks along body x
  f.rig.T_BC0.linear() = R;
  f.rig.T_BC1 = f.rig.T_BC0;
  f.rig.T_BC1.translation() = R * Eigen::Vector3d(0.11, 0, 0);
  f.rig.focal_px = 458;
  f.imu.R = so3::exp(Eigen::Vector3d(0.0, 0.02, 0.01));
  f.imu.t = Eigen::Vector3d(0.4, 0.05, 0.0);
  f.imu.covariance.setZero();
  f.imu.covariance.diagonal() << 2.5e-5, 2.5e-5, 2.5e-5, 1e-4, 1e-4, 1e-4;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0), depth(2.0, 8.0);
  std::normal_distribution<double> px(0.0, 0.5 / f.rig.focal_px);
  const Eigen::Isometry3d T_CB = f.rig.T_BC0.inverse();
  for (int i = 0; i < 150; ++i) {
    TrackedPoint p;
    p.track_id = static_cast<std::uint64_t>(i);
    const double d = depth(rng);
    const Eigen::Vector3d b(0.6 * u(rng), 0.4 * u(rng), 1.0);
    p.X_r = f.rig.T_BC0 * (b * d);
    p.depth_r = d;
    p.ray_r = f.rig.T_BC0.linear() * b.normalized();
    p.depth_sigma_r = d * d * 0.5 / (f.rig.focal_px * 0.11);
    const bool moved = object_on_one_side ? b.x() > 0.2 : i % 3 == 0;
    p.X_k = f.imu.toCurrent(p.X_r) + (moved ? Eigen::Vector3d(0, 0.05, 0) : Eigen::Vector3d::Zero());
    const Eigen::Vector3d c = T_CB * p.X_k;
    p.n0_k = c.head<2>() / c.z() + Eigen::Vector2d(px(rng), px(rng));
    p.has_X_k = true;
    p.depth_sigma_k = c.z() * c.z() * 0.5 / (f.rig.focal_px * 0.11);
    f.points.push_back(p);
  }
  return f;
}

void BM_RelativePoseSolver(benchmark::State& state) {
  const Frame f = makeFrame(false);
  const RelativePoseSolver solver(f.rig, {});
  for (auto _ : state) benchmark::DoNotOptimize(solver.solve(f.points, f.imu));
}
BENCHMARK(BM_RelativePoseSolver)->Unit(benchmark::kMicrosecond);

void BM_LandmarkConflictDetector(benchmark::State& state) {
  const Frame f = makeFrame(false);
  const LandmarkConflictDetector detector(f.rig, ConflictOptions{});
  for (auto _ : state) benchmark::DoNotOptimize(detector.test(f.points, f.imu));
}
BENCHMARK(BM_LandmarkConflictDetector)->Unit(benchmark::kMicrosecond);

/// Arg 0: moved points scattered (no side moves: the steps only); 1: the right third moves.
void BM_RegionSplitDetector(benchmark::State& state) {
  const Frame f = makeFrame(state.range(0) == 1);
  const RegionSplitDetector detector(f.rig, {}, RelativePoseSolver(f.rig, {}));
  state.counters["fired"] = detector.test(f.points, f.imu, f.imu).fired ? 1 : 0;
  for (auto _ : state) benchmark::DoNotOptimize(detector.test(f.points, f.imu, f.imu));
}
BENCHMARK(BM_RegionSplitDetector)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
