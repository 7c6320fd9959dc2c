// Rays per second of the voxel walk on a 128^3 grid with a realistic sparse foreground (three
// visitors around the pyramid), dense DDA versus empty-space skipping, plus the per-frame cost of
// rebuilding the grid. Rays start on a relic-sized sphere and leave in random directions, as
// reflected rays do. Single-threaded: multiply by cores for a frame estimate.
#include <benchmark/benchmark.h>

#include <random>

#include "holo/reflect/voxel_walk.hpp"
#include "synthetic_foreground.hpp"

namespace {

using namespace holo;

reflect::VoxelGridSettings settings128(int brick) {
  reflect::VoxelGridSettings s;
  s.bounds = {vec3(-1.6f, 0.0f, -1.6f), vec3(1.6f, 3.2f, 1.6f)};
  s.voxel_size = 0.025f;  // 128^3
  s.brick_size = brick;
  return s;
}

std::vector<Ray> relicRays(std::size_t count) {
  std::mt19937 rng(11);
  std::normal_distribution<float> n(0.0f, 1.0f);
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    const vec3 s = glm::normalize(vec3(n(rng), n(rng), n(rng)) + vec3(1e-6f));
    r.origin = vec3(0.0f, 0.3f, 0.0f) + 0.15f * s;
    vec3 d = glm::normalize(vec3(n(rng), n(rng), n(rng)) + vec3(1e-6f));
    if (glm::dot(d, s) < 0.0f) d = -d;  // leaves the surface
    r.direction = d;
  }
  return rays;
}

void walk(benchmark::State& state, reflect::WalkMode mode, int visitors) {
  reflect::VoxelGrid grid(settings128(int(state.range(0))));
  grid.build(holo::test::visitorCloud(visitors, 0.7f, 5));
  const std::vector<Ray> rays = relicRays(1 << 16);
  reflect::WalkStats stats;
  std::size_t i = 0, hits = 0;
  for (auto _ : state) {
    const reflect::VoxelHit h = reflect::firstOccupiedVoxel(grid, rays[i], 100.0f, mode, &stats);
    hits += h.hit() ? 1 : 0;
    benchmark::DoNotOptimize(h);
    i = (i + 1) & (rays.size() - 1);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()));
  state.counters["hit_fraction"] = double(hits) / double(state.iterations());
  state.counters["voxel_steps_per_ray"] = double(stats.voxel_steps) / double(state.iterations());
  state.counters["brick_steps_per_ray"] = double(stats.brick_steps) / double(state.iterations());
  state.counters["occupied_voxels"] = double(grid.occupiedCount());
}

void BM_WalkDense(benchmark::State& s) {
  walk(s, reflect::WalkMode::Dense, int(s.range(1)));
}
void BM_WalkSkipping(benchmark::State& s) {
  walk(s, reflect::WalkMode::Skipping, int(s.range(1)));
}
BENCHMARK(BM_WalkDense)->Args({8, 3});
BENCHMARK(BM_WalkSkipping)->Args({4, 3})->Args({8, 3})->Args({16, 3})->Args({8, 0})->Args({8, 1});

void BM_GridRebuild(benchmark::State& state) {
  reflect::VoxelGrid grid(settings128(8));
  const depthfilter::ForegroundCloud cloud = holo::test::visitorCloud(3, 0.7f, 5);
  for (auto _ : state) {
    grid.build(cloud);
    benchmark::DoNotOptimize(grid.occupiedCount());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations() * cloud.points.size()));
  state.counters["points"] = double(cloud.points.size());
}
BENCHMARK(BM_GridRebuild)->Unit(benchmark::kMicrosecond);

}  // namespace
