// The AR composite's cost per pixel sample at the cameras' 640x360 (ar_test_scene.hpp: a sphere
// on a plane under a small sun): delta path tracing, two-pass differential rendering, the change
// filter. Read medians and ratios from a run by hand.
#include <benchmark/benchmark.h>

#include "ar_test_scene.hpp"
#include "holo/ar/change_filter.hpp"
#include "holo/ar/local_path_tracing.hpp"

namespace holo::ar {
namespace {

struct Fixture {
  cv::Mat panorama = test::sunnyPanorama();
  reflect::Environment environment{panorama};
  LocalScene scene{test::plane(), test::sphereRelic(), environment};
  CameraModel view = test::camera(640, 360);
  cv::Mat background = cv::Mat(360, 640, CV_32FC3, cv::Scalar::all(0.2));
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void composite(benchmark::State& state, DifferentialMethod method) {
  const Fixture& f = fixture();
  CompositeSettings settings;
  settings.method = method;
  settings.spp = 1;
  std::int64_t rays = 0;
  for (auto _ : state) {
    const CompositeImage image = renderComposite(f.scene, f.view, f.background, settings);
    rays += image.rays;
    ++settings.first_sample;
    benchmark::DoNotOptimize(image.radiance.data);
  }
  state.counters["rays_per_sample"] =
      static_cast<double>(rays) / (static_cast<double>(state.iterations()) * 640 * 360);
}

void BM_DeltaPathTracing(benchmark::State& state) {
  composite(state, DifferentialMethod::kDeltaPathTracing);
}
void BM_TwoPassDifferential(benchmark::State& state) {
  composite(state, DifferentialMethod::kTwoPass);
}
void BM_ChangeFilter(benchmark::State& state) {
  const Fixture& f = fixture();
  CompositeSettings settings;
  settings.spp = 1;
  const CompositeImage image = renderComposite(f.scene, f.view, f.background, settings);
  const cv::Mat depth(360, 640, CV_32FC1, cv::Scalar(1.0f));
  for (auto _ : state) {
    const cv::Mat filtered = filterChange(image.radiance, f.background, image.relic_coverage, depth, {});
    benchmark::DoNotOptimize(filtered.data);
  }
}
BENCHMARK(BM_DeltaPathTracing)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TwoPassDifferential)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ChangeFilter)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace holo::ar
