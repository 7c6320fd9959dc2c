// Simulated frame generation time per camera, at the default 640x360, and the panorama.
#include <benchmark/benchmark.h>

#include "holo/sim/museum.hpp"

namespace {

const holo::sim::Museum& museum() {
  static const holo::sim::Museum m(holo::sim::loadScene("museum"));
  return m;
}

void BM_RenderCamera(benchmark::State& state) {
  int frame = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(museum().renderCamera(frame % 4, frame));
    ++frame;
  }
  state.SetLabel("640x360, one camera, visitors + noise");
}
BENCHMARK(BM_RenderCamera)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RenderPanorama(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(museum().renderPanorama(1024, 512));
}
BENCHMARK(BM_RenderPanorama)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

}  // namespace
