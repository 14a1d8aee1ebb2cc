// Rendering speed of the simulator: stereo pairs per second for each scenario's world, with the
// default options (EuRoC 752x480 stereo, 1024-texel textures, 2 render threads), with either
// texture filter (third argument: 0 isotropic, 1 anisotropic).
#include <benchmark/benchmark.h>

#include "mcvio/sim/feature_simulator.hpp"
#include "mcvio/sim/simulator.hpp"

namespace {

void BM_RenderStereoPair(benchmark::State& state) {
  mcvio::sim::SimulatorOptions o;
  o.scenario.kind = static_cast<mcvio::sim::ScenarioKind>(state.range(0));
  o.threads = static_cast<int>(state.range(1));
  o.texture_filter = static_cast<mcvio::sim::TextureFilter>(state.range(2));
  const mcvio::sim::Simulator sim(o);
  std::size_t k = 0;
  for (auto _ : state) {
    auto frame = sim.renderFrame(k);
    benchmark::DoNotOptimize(frame.cam0.data);
    k = (k + 37) % sim.frameTimes().size();  // spread over the whole trajectory
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
  state.SetLabel(std::string(mcvio::sim::toString(o.scenario.kind)) + ", " + mcvio::sim::toString(o.texture_filter) +
                 ", items = stereo pairs");
}
BENCHMARK(BM_RenderStereoPair)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {2}, {0, 1}})
    ->Args({0, 1, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_FeatureSequence60s(benchmark::State& state) {
  mcvio::sim::SimulatorOptions o;
  o.scenario.kind = mcvio::sim::ScenarioKind::kPedestrian;
  for (auto _ : state) {
    auto seq = mcvio::sim::simulateFeatureSequence(o);
    benchmark::DoNotOptimize(seq.frames.data());
  }
  state.SetLabel("60 s, 1201 stereo feature frames");
}
BENCHMARK(BM_FeatureSequence60s)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
