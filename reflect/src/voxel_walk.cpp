#include "holo/reflect/voxel_walk.hpp"

#include <algorithm>
#include <cmath>

namespace holo::reflect {
namespace {

using glm::ivec3;

// The ray in grid units with its reciprocal direction, computed once per walk: the DDA and the
// box clips multiply instead of divide. A zero component (+0.0 or -0.0) has inv = 0 and is
// handled explicitly, never through 0 * inf.
struct GridRay {
  vec3 o, d, inv;
  // The ray in units of `size` cells (s = 1 / size). A power-of-two size scales the reciprocal by
  // a multiplication, which is exactly the division by s and costs a fraction of it.
  GridRay scaled(float s, int size) const {
    const bool power_of_two = (size & (size - 1)) == 0;
    return {o * s, d * s, power_of_two ? inv * float(size) : inv / s};
  }
};

GridRay makeGridRay(const vec3& o, const vec3& d) {
  GridRay r{o, d, vec3(0.0f)};
  for (int a = 0; a < 3; ++a)
    if (d[a] != 0.0f) r.inv[a] = 1.0f / d[a];
  return r;
}

// Clips the ray to the box [lo, hi) and to [t0, t1]. A zero direction component keeps the ray in
// one slab: inside iff lo <= o < hi (half-open, as voxels are). Returns false when nothing is left.
bool clipToBox(const GridRay& r, const vec3& lo, const vec3& hi, float& t0, float& t1) {
  for (int a = 0; a < 3; ++a) {
    if (r.d[a] == 0.0f) {
      if (!(r.o[a] >= lo[a] && r.o[a] < hi[a])) return false;
      continue;
    }
    float ta = (lo[a] - r.o[a]) * r.inv[a];
    float tb = (hi[a] - r.o[a]) * r.inv[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

// Amanatides-Woo DDA over the integer box [lo, hi) for t in [t0, t1] (already clipped to the
// box). visit(cell, t_enter) returns true to stop. Returns false when the step cap was reached.
template <typename Visit>
bool dda(const GridRay& r, const ivec3& lo, const ivec3& hi, float t0, float t1, std::uint64_t& steps,
         Visit&& visit) {
  const vec3 p = r.o + r.d * t0;
  // Round-off may put the entry point a hair outside the box: clamp into it. The point is first
  // clamped to [lo - 1, hi] in float (no int overflow far away), where truncation corrected by one
  // below zero is the floor (without SSE4.1 floorf is a call or a long sequence); the cell is
  // clamp(floor(p), lo, hi - 1) as before.
  ivec3 cell;
  for (int a = 0; a < 3; ++a) {
    const float x = std::clamp(p[a], float(lo[a] - 1), float(hi[a]));
    const int truncated = int(x);
    cell[a] = std::clamp(float(truncated) > x ? truncated - 1 : truncated, lo[a], hi[a] - 1);
  }
  ivec3 step(0);
  vec3 t_next(std::numeric_limits<float>::infinity());
  vec3 t_delta(std::numeric_limits<float>::infinity());
  for (int a = 0; a < 3; ++a) {
    if (r.d[a] > 0.0f) {
      step[a] = 1;
      t_delta[a] = r.inv[a];
      t_next[a] = (float(cell[a] + 1) - r.o[a]) * r.inv[a];
    } else if (r.d[a] < 0.0f) {
      step[a] = -1;
      t_delta[a] = -r.inv[a];
      t_next[a] = (float(cell[a]) - r.o[a]) * r.inv[a];
    }
    // d[a] == 0 (+0.0 or -0.0): the walk never leaves this slab; t_next stays infinite.
  }
  // A correct walk moves monotonically along every axis, so it visits at most the sum of the
  // box's extents plus one cells; the slack covers clamped starts.
  const ivec3 extent = hi - lo;
  const int cap = extent.x + extent.y + extent.z + 4;
  float t = t0;
  for (int i = 0; i < cap; ++i) {
    ++steps;
    if (visit(cell, t)) return true;
    const int a = (t_next.x < t_next.y) ? (t_next.x < t_next.z ? 0 : 2) : (t_next.y < t_next.z ? 1 : 2);
    if (!(t_next[a] <= t1)) return true;  // leaves [t0, t1] first (or every axis is parallel)
    t = std::max(t, t_next[a]);
    cell[a] += step[a];
    if (cell[a] < lo[a] || cell[a] >= hi[a]) return true;
    t_next[a] += t_delta[a];
  }
  return false;
}

}  // namespace

VoxelHit firstOccupiedVoxel(const VoxelGrid& grid, const Ray& ray, float t_max, WalkMode mode,
                            WalkStats* stats) {
  VoxelHit hit;
  WalkStats local;
  WalkStats& st = stats ? *stats : local;
  if (grid.empty() || !isFinite(ray.origin) || !isFinite(ray.direction) || std::isnan(t_max) ||
      !(t_max >= 0.0f) || ray.direction == vec3(0.0f))
    return hit;

  // Grid coordinates: voxel (i, j, k) is [i, i+1) x [j, j+1) x [k, k+1); t is unchanged.
  const float inv_size = grid.inverseVoxelSize();
  const GridRay r = makeGridRay((ray.origin - grid.origin()) * inv_size, ray.direction * inv_size);

  auto visit_voxel = [&](const ivec3& v, float t_enter) {
    if (!grid.occupiedBit(v)) return false;
    hit.sample = grid.sampleIndex(v);
    hit.voxel = v;
    hit.t = t_enter;
    return true;
  };

  if (mode == WalkMode::Dense) {
    float t0 = 0.0f, t1 = t_max;
    if (!clipToBox(r, vec3(0.0f), vec3(grid.dims()), t0, t1)) return hit;
    if (!dda(r, ivec3(0), grid.dims(), t0, t1, st.voxel_steps, visit_voxel)) {
      ++st.capped;
      return VoxelHit{};
    }
    return hit;
  }

  // Skipping: clip to the occupied bounds, walk bricks, descend into non-empty ones.
  const ivec3 occ_lo = grid.occupiedLo();
  const ivec3 occ_hi = grid.occupiedHi();
  float t0 = 0.0f, t1 = t_max;
  if (!clipToBox(r, vec3(occ_lo), vec3(occ_hi), t0, t1)) return hit;

  const int b = grid.brickSize();
  const float inv_b = grid.inverseBrickSize();
  const ivec3 brick_lo = occ_lo / b;
  const ivec3 brick_hi = (occ_hi - 1) / b + 1;
  const GridRay rb = r.scaled(inv_b, b);
  bool capped = false;
  float t_restart = t0;  // set when an empty brick lets the walk jump
  auto visit_brick = [&](const ivec3& brick, float t_enter) {
    // The brick distance is 0 exactly where the brick holds an occupied voxel: one byte read
    // decides both whether to descend and how far the empty space around reaches.
    const int k = grid.brickDistance(brick);
    if (k != 0) {
      // Every brick within distance - 1 of this one is empty: jump to where the ray leaves
      // that cube (restarting the brick DDA there) when it saves at least one step.
      if (k < 2) return false;
      float t_exit = t1;
      for (int a = 0; a < 3; ++a) {
        if (rb.d[a] == 0.0f) continue;
        const float face = rb.d[a] > 0.0f ? float(brick[a] + k) : float(brick[a] - k + 1);
        t_exit = std::min(t_exit, (face - rb.o[a]) * rb.inv[a]);
      }
      if (!(t_exit > t_enter)) return false;
      t_restart = t_exit;
      return true;
    }
    const ivec3 base = brick * b;
    const ivec3 lo = glm::max(base, occ_lo);
    const ivec3 hi = glm::min(base + b, occ_hi);
    // Re-clip in voxel units: exact bounds for the fine walk, no drift from the brick level.
    float s0 = t0, s1 = t1;
    if (!clipToBox(r, vec3(lo), vec3(hi), s0, s1)) return false;
    const auto visit_in_brick = [&](const ivec3& v, float t_enter_voxel) {
      const ivec3 in_brick = v - base;
      if (!grid.occupiedInBrick(brick, in_brick)) return false;
      hit.sample = grid.sampleInBrick(brick, in_brick);
      hit.voxel = v;
      hit.t = t_enter_voxel;
      return true;
    };
    if (!dda(r, lo, hi, s0, s1, st.voxel_steps, visit_in_brick)) {
      capped = true;
      return true;
    }
    return hit.hit();
  };
  // Restarts happen only after a jump that moved t forward by at least one brick, so their
  // number is bounded by the brick extents as well.
  const ivec3 brick_extent = brick_hi - brick_lo;
  const int max_restarts = brick_extent.x + brick_extent.y + brick_extent.z + 4;
  for (int restart = 0;; ++restart) {
    if (restart > max_restarts) {
      ++st.capped;
      return VoxelHit{};
    }
    const float start = t_restart;
    t_restart = -1.0f;
    const bool finished = dda(rb, brick_lo, brick_hi, start, t1, st.brick_steps, visit_brick);
    if (!finished || capped) {
      ++st.capped;
      return VoxelHit{};
    }
    if (hit.hit() || !(t_restart > start) || !(t_restart <= t1)) break;
  }
  return hit;
}

}  // namespace holo::reflect
