// Speed of the reflection ground truth and of the prefiltered IBL (the bars: IBL build
// "well under a second" for a 1024x512 panorama on two cores; path-tracer throughput in samples
// per second). Run: build/tests/reflect/bench_reflect
#include <benchmark/benchmark.h>

#include <tbb/global_control.h>
#include <filesystem>
#include <random>

#include "holo/core/hdr_io.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/view.hpp"
#include "reflect_test_scenes.hpp"
#include "shared_data.hpp"

namespace holo::reflect {
namespace {

using reference::PathTracer;
using reference::PathTracerStats;
using reference::renderPathTraced;

// The real interior panorama when the shared data is there, else a seeded noise panorama with
// a sun of the same size (the build cost does not depend on the content much).
const cv::Mat& panorama1k() {
  static const cv::Mat pano = [] {
    const auto path = test::sharedData("hdri/st_fagans_interior_1k.hdr");
    if (std::filesystem::exists(path)) return loadHdr(path).pixels;
    cv::Mat p(512, 1024, CV_32FC3);
    cv::randu(p, cv::Scalar::all(0.0), cv::Scalar::all(2.0));
    p(cv::Rect(500, 100, 4, 4)).setTo(cv::Scalar::all(5e4));
    return p;
  }();
  return pano;
}

void BM_PrefilterBuild1024x512TwoThreads(benchmark::State& state) {
  const tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
  const Environment env(panorama1k());
  for (auto _ : state) {
    const PrefilteredIbl ibl(env);
    benchmark::DoNotOptimize(ibl.levelCount());
  }
}
BENCHMARK(BM_PrefilterBuild1024x512TwoThreads)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_EnvironmentBuild1024x512(benchmark::State& state) {
  for (auto _ : state) {
    const Environment env(panorama1k());
    benchmark::DoNotOptimize(env.integral());
  }
}
BENCHMARK(BM_EnvironmentBuild1024x512)->Unit(benchmark::kMillisecond);

void BM_IblShadeLookup(benchmark::State& state) {
  const Environment env(panorama1k());
  const PrefilteredIbl ibl(env);
  std::mt19937 rng(1);
  std::normal_distribution<float> g;
  std::vector<vec3> dirs(4096);
  for (vec3& d : dirs) d = glm::normalize(vec3(g(rng), g(rng), g(rng)));
  const SurfaceMaterial m{vec3(0.9f, 0.7f, 0.4f), 1.0f, 0.35f, 1.0f};
  std::size_t i = 0;
  for (auto _ : state) {
    const vec3& n = dirs[i++ & 4095];
    benchmark::DoNotOptimize(ibl.shade(m, n, glm::normalize(n + dirs[(i * 7) & 4095] * 0.5f), vec3(0.0f)));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_IblShadeLookup);

void BM_PathTracerThroughput(benchmark::State& state) {
  const tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
  const Environment env(panorama1k());
  const RenderScene scene(test::sphereModel({vec3(0.9f, 0.7f, 0.4f), 1.0f, 0.35f, 1.0f}), {});
  const PathTracer tracer(scene, env);
  const CameraModel camera = lookAtCamera(vec3(0, 0.5f, 3.2f), vec3(0.0f), 40.0f, 64, 64);
  std::int64_t samples = 0;
  for (auto _ : state) {
    PathTracerStats stats;
    benchmark::DoNotOptimize(renderPathTraced(tracer, camera, 4, &stats));
    samples += stats.samples;
  }
  state.counters["samples/s"] = benchmark::Counter(double(samples), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PathTracerThroughput)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace holo::reflect
