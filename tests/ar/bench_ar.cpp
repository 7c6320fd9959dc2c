// The AR composite's cost per pixel sample at the cameras' 640x360 (ar_test_scene.hpp: a sphere
// on a plane under a small sun): delta path tracing, two-pass differential rendering (independent
// and shared samples), the change filter, and a still frame of the live view (live_composite.hpp:
// the change test, one sample per pixel added, the filter). Read medians and ratios from a run by
// hand.
#include <benchmark/benchmark.h>

#include "ar_test_scene.hpp"
#include "holo/ar/change_filter.hpp"
#include "holo/ar/live_composite.hpp"
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
void BM_TwoPassSharedSamples(benchmark::State& state) {
  composite(state, DifferentialMethod::kTwoPassSharedSamples);
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
// A still frame of the live view: the plane's depth, a flat grey image.
void BM_LiveCompositeStillFrame(benchmark::State& state) {
  const Fixture& f = fixture();
  RgbdFrame frame;
  frame.colour = cv::Mat(360, 640, CV_8UC3, cv::Scalar::all(120));
  frame.depth = cv::Mat::zeros(360, 640, CV_32FC1);
  const vec3 forward = glm::normalize(vec3(f.view.T_world_camera()[2]));
  for (int y = 0; y < 360; ++y)
    for (int x = 0; x < 640; ++x) {
      const Ray ray = f.view.ray({static_cast<float>(x), static_cast<float>(y)});
      if (ray.direction.y < 0.0f)
        frame.depth.at<float>(y, x) = -ray.origin.y / ray.direction.y * glm::dot(ray.direction, forward);
    }
  LiveCompositeSettings settings;
  settings.view.composite.spp = 1;
  settings.max_samples = 1 << 20;
  LiveComposite live(0, f.view, f.panorama, test::sphereRelic(), settings);
  live.add(frame);  // the first frame builds the local scene
  for (auto _ : state) {
    const LiveCompositeFrame out = live.add(frame);
    benchmark::DoNotOptimize(out.image.data);
  }
}
BENCHMARK(BM_DeltaPathTracing)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TwoPassDifferential)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TwoPassSharedSamples)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ChangeFilter)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LiveCompositeStillFrame)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace holo::ar
