// Speed of the reflection ground truth, of the prefiltered IBL (the bars: IBL build "well under a
// second" for a 1024x512 panorama on two cores; path-tracer throughput in samples per second) and
// of casting a view's primary rays at the relic. Run: build/tests/reflect/bench_reflect
#include <benchmark/benchmark.h>

#include <tbb/global_control.h>
#include <filesystem>
#include <random>

#include "holo/core/denormals.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/ray_scene.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"
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

// The primary rays of one 540x540 view of the museum's vase from a visitor's eye, on one thread,
// as `bench frame`'s packet floor casts them (8x8 tiles, flush-to-zero): one at a time (argument
// 1) or in coherent packets of 8 or 16 rays. The floor and the hit points cast packets of
// RayScene::nativePacketWidth(), which this shows is the fastest on the CPU at hand.
void BM_RelicPrimaryRays(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  RayScene relic;
  const Model vase = relics::makeRelic("vase");
  for (const TriangleMesh& mesh : vase.meshes) relic.addMesh(mesh);
  relic.commit();
  if (width > 1) relic.setPacketWidth(width);
  const Bounds3 box = vase.bounds();
  const vec3 eye = box.center() + faceDirection(0) * kDefaultEyeDistance + vec3(0.0f, 0.4f, 0.0f);
  constexpr int kSize = 540, kTile = 8;
  const CameraModel view = lookAtCamera(eye, box.center(), framingFovDeg(eye, box), kSize, kSize);
  const FlushDenormals flush;
  std::array<Ray, kTile * kTile> rays;
  std::array<RayHit, kTile * kTile> hits;
  std::int64_t relic_hits = 0;
  for (auto _ : state) {
    relic_hits = 0;
    for (int y0 = 0; y0 < kSize; y0 += kTile)
      for (int x0 = 0; x0 < kSize; x0 += kTile) {
        std::size_t n = 0;
        for (int y = y0; y < std::min(y0 + kTile, kSize); ++y)
          for (int x = x0; x < std::min(x0 + kTile, kSize); ++x)
            rays[n++] = primaryRay(view, vec2(float(x) + 0.5f, float(y) + 0.5f));
        if (width > 1) {
          relic.intersectCoherent(std::span(rays).first(n), std::span(hits).first(n));
        } else {
          for (std::size_t i = 0; i < n; ++i) hits[i] = relic.intersect(rays[i]);
        }
        for (std::size_t i = 0; i < n; ++i) relic_hits += hits[i].hit() ? 1 : 0;
      }
  }
  state.counters["relic_pixels"] = double(relic_hits);
  state.SetItemsProcessed(state.iterations() * kSize * kSize);
}
BENCHMARK(BM_RelicPrimaryRays)->Arg(1)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace holo::reflect
