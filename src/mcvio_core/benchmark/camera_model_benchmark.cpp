// Camera model throughput on EuRoC cam0 (radial-tangential): project and unproject.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "mcvio/core/camera_model.hpp"

namespace {

mcvio::CameraModel eurocCam0() {
  return mcvio::CameraModel(752, 480, {458.654, 457.296, 367.215, 248.375},
                            mcvio::DistortionModel::kRadialTangential,
                            {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
}

std::vector<Eigen::Vector2d> randomPixels(std::size_t n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.0, 751.0), v(0.0, 479.0);
  std::vector<Eigen::Vector2d> pixels(n);
  for (auto& p : pixels) p = {u(rng), v(rng)};
  return pixels;
}

void BM_Unproject(benchmark::State& state) {
  const mcvio::CameraModel cam = eurocCam0();
  const auto pixels = randomPixels(1024);
  std::size_t i = 0;
  for (auto _ : state) {
    Eigen::Vector2d n;
    benchmark::DoNotOptimize(cam.unproject(pixels[i++ & 1023], &n));
    benchmark::DoNotOptimize(n);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_Unproject);

void BM_ProjectWithJacobian(benchmark::State& state) {
  const mcvio::CameraModel cam = eurocCam0();
  std::vector<Eigen::Vector3d> points;
  for (const auto& px : randomPixels(1024)) {
    Eigen::Vector3d b;
    cam.unprojectBearing(px, &b);
    points.push_back(3.0 * b);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    Eigen::Vector2d px;
    Eigen::Matrix<double, 2, 3> J;
    benchmark::DoNotOptimize(cam.project(points[i++ & 1023], &px, &J));
    benchmark::DoNotOptimize(J);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_ProjectWithJacobian);

}  // namespace

BENCHMARK_MAIN();
