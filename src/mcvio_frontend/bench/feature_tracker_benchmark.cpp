// Time per stereo frame of FeatureTracker at 752x480, single thread.
//   real EuRoC V1_01 excerpt (needs MCVIO_SHARED_DIR, default ../shared next to the repo) and
//   the synthetic moving scene (replenishment every frame).
// MCVIO_FRONTEND_OPTIONS=<yaml file> overrides the default options.
// Counters: cpu_median_ms / cpu_p90_ms per frame (thread CPU time, immune to other load on
// the machine), wall_median_ms, mean CPU time per stage, features and stereo matches per frame.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <opencv2/core/utility.hpp>
#include <vector>

#include "euroc_excerpt.hpp"
#include "mcvio/frontend/feature_tracker.hpp"
#include "synthetic_stereo_scene.hpp"

namespace mcvio::frontend {
namespace {

void runFrames(benchmark::State& state, const StereoRigCalibration& calib,
               const std::vector<StereoInput>& frames, Timestamp period) {
  // MCVIO_FRONTEND_OPTIONS=<yaml> benchmarks other settings than the defaults.
  const char* options_file = std::getenv("MCVIO_FRONTEND_OPTIONS");
  FeatureTracker tracker(options_file ? FrontendOptions::fromFile(options_file)
                                      : FrontendOptions());
  tracker.setCalibration(calib);
  std::vector<double> ms, cpu_ms;
  double prepare = 0, temporal = 0, detect = 0, stereo_ms = 0;
  double features = 0, stereo = 0;
  std::size_t i = 0;
  Timestamp offset = 0;
  const Timestamp span = frames.back().t - frames.front().t + period;
  for (auto _ : state) {
    StereoInput in = frames[i];
    in.t += offset;
    for (auto& s : in.imu) s.t += offset;
    const auto t0 = std::chrono::steady_clock::now();
    const TrackingResult r = tracker.track(in);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(r);
    if (!r.ok()) {
      state.SkipWithError(r.message.c_str());
      break;
    }
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    cpu_ms.push_back(r.stats.cpu_ms_total);
    prepare += r.stats.cpu_ms_prepare;
    temporal += r.stats.cpu_ms_temporal;
    detect += r.stats.cpu_ms_detect;
    stereo_ms += r.stats.cpu_ms_stereo;
    features += r.stats.tracked + r.stats.detected;
    stereo += r.stats.stereo_matched;
    if (++i == frames.size()) {
      i = 0;
      offset += span;
    }
  }
  if (ms.empty()) return;
  std::sort(ms.begin(), ms.end());
  std::sort(cpu_ms.begin(), cpu_ms.end());
  const double n = static_cast<double>(ms.size());
  state.counters["wall_median_ms"] = ms[ms.size() / 2];
  state.counters["cpu_median_ms"] = cpu_ms[cpu_ms.size() / 2];
  state.counters["cpu_p90_ms"] = cpu_ms[cpu_ms.size() * 9 / 10];
  state.counters["cpu_prepare_ms"] = prepare / n;
  state.counters["cpu_temporal_ms"] = temporal / n;
  state.counters["cpu_detect_ms"] = detect / n;
  state.counters["cpu_stereo_ms"] = stereo_ms / n;
  state.counters["features"] = features / static_cast<double>(ms.size());
  state.counters["stereo"] = stereo / static_cast<double>(ms.size());
}

void BM_TrackEurocExcerpt(benchmark::State& state) {
  if (!std::getenv("MCVIO_SHARED_DIR")) setenv("MCVIO_SHARED_DIR", MCVIO_DEFAULT_SHARED_DIR, 0);
  const auto mav0 = testing::EurocExcerpt::locate();
  if (!mav0) {
    state.SkipWithError("EuRoC excerpt not found (set MCVIO_SHARED_DIR)");
    return;
  }
  static const testing::EurocExcerpt excerpt(*mav0);
  static std::vector<StereoInput> frames;
  if (frames.empty()) {
    for (std::size_t k = 0; k < excerpt.size(); ++k) frames.push_back(excerpt.frame(k));
  }
  runFrames(state, excerpt.calibration(), frames, 50'000'000);
}
BENCHMARK(BM_TrackEurocExcerpt)->Unit(benchmark::kMillisecond)->Iterations(950);

void BM_TrackSyntheticMoving(benchmark::State& state) {
  static const testing::SyntheticStereoScene scene({});
  static std::vector<StereoInput> frames;
  if (frames.empty()) {
    for (int k = 0; k < 60; ++k) frames.push_back(scene.render(k));
  }
  runFrames(state, scene.calibration(), frames, 50'000'000);
}
BENCHMARK(BM_TrackSyntheticMoving)->Unit(benchmark::kMillisecond)->Iterations(600);

}  // namespace
}  // namespace mcvio::frontend

int main(int argc, char** argv) {
  cv::setNumThreads(1);  // one core: the figure must not depend on OpenCV's thread pool
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
