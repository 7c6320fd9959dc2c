// The voxel walk: the first occupied voxel of the foreground grid along a ray, by the 3D DDA of
// Amanatides and Woo ("A fast voxel traversal algorithm for ray tracing", 1987), with
// empty-space skipping.
//
// Semantics. Voxels are half-open boxes (see voxel_grid.hpp). The walk returns the
// occupied voxel the ray enters first for t in [0, t_max], and the t at which it enters it (0 when
// the origin lies inside). Where the ray only grazes voxels (passes exactly along a face, an edge
// or through a corner) either neighbour may be reported: such contacts have zero length.
//
// Skipping mode clips the ray to the occupied voxel bounds, walks the brick level and descends
// into bricks that hold occupied voxels only; Dense mode walks every voxel of the grid box (the
// reference the benchmark compares against). Both give the same hits.
//
// Robustness. Axis-parallel directions and -0.0 components are handled without dividing by zero;
// origins outside the grid, on faces or corners work; a zero, non-finite or NaN ray misses. Every
// DDA loop has a step cap (the box's dimensions summed, plus slack) that a correct walk cannot
// reach; reaching it counts in WalkStats::capped and returns a miss.
#pragma once

#include <cstdint>
#include <limits>

#include "holo/core/math.hpp"
#include "holo/reflect/voxel_grid.hpp"

namespace holo::reflect {

enum class WalkMode { Dense, Skipping };

struct VoxelHit {
  std::int32_t sample = -1;  // index into VoxelGrid::sample, -1 on a miss
  glm::ivec3 voxel{-1};
  float t = std::numeric_limits<float>::infinity();  // ray parameter (metres for a unit direction)
  bool hit() const { return sample >= 0; }
};

// Counters for benchmarks and tests (not thread-safe: one per thread).
struct WalkStats {
  std::uint64_t voxel_steps = 0;  // fine-level cells visited
  std::uint64_t brick_steps = 0;  // brick-level cells visited
  std::uint64_t capped = 0;       // walks that hit the step cap (a bug if ever non-zero)
};

// First occupied voxel along `ray` for t in [0, t_max]. The direction need not be unit length;
// t is in units of its length.
VoxelHit firstOccupiedVoxel(const VoxelGrid& grid, const Ray& ray,
                            float t_max = std::numeric_limits<float>::infinity(),
                            WalkMode mode = WalkMode::Skipping, WalkStats* stats = nullptr);

}  // namespace holo::reflect
