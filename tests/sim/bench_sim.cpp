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

// The same frames under the structured-light profile: its shadow scan, edge map and patch noise
// on top of the ray casting.
void BM_RenderCameraStructuredLight(benchmark::State& state) {
  static const holo::sim::Museum m = [] {
    auto scene = holo::sim::loadScene("museum");
    scene.noise = holo::sim::sensorProfile(holo::sim::SensorProfile::structured_light);
    return holo::sim::Museum(scene);
  }();
  int frame = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.renderCamera(frame % 4, frame));
    ++frame;
  }
  state.SetLabel("640x360, one camera, visitors + structured-light sensor");
}
BENCHMARK(BM_RenderCameraStructuredLight)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RenderPanorama(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(museum().renderPanorama(1024, 512));
}
BENCHMARK(BM_RenderPanorama)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

}  // namespace
