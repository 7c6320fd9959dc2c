// The voxel walk against a brute-force reference on a million rays (random and adversarial).
#include "holo/reflect/voxel_walk.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "synthetic_foreground.hpp"

namespace holo::reflect {
namespace {

using depthfilter::ForegroundCloud;
using depthfilter::ForegroundPoint;

constexpr float kInf = std::numeric_limits<float>::infinity();

// Closed-box ray interval [t_in, t_out] within [0, t_max], computed in double with explicit
// handling of zero components; empty when t_in > t_out.
struct Interval {
  double t_in, t_out;
  bool empty() const { return !(t_in <= t_out); }
};
Interval boxInterval(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi,
                     double t_max) {
  Interval iv{0.0, t_max};
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return {1.0, 0.0};
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    iv.t_in = std::max(iv.t_in, ta);
    iv.t_out = std::min(iv.t_out, tb);
  }
  return iv;
}

// A voxel's box shrunk and grown by eps (metres): a ray through the shrunk box must be found;
// one that misses the grown box must not be reported. Between the two lie grazing contacts
// (along a face, an edge or a corner, or off by the round-off of the world-to-grid transform),
// which may go either way.
struct Contact {
  Interval inner, outer;
};
Contact contact(const Ray& ray, const glm::dvec3& lo, const glm::dvec3& hi, double t_max, double eps) {
  const glm::dvec3 o(ray.origin), d(ray.direction);
  return {boxInterval(o, d, lo + eps, hi - eps, t_max), boxInterval(o, d, lo - eps, hi + eps, t_max)};
}

struct OccupiedBox {
  glm::ivec3 voxel;
  glm::dvec3 lo, hi;
};

std::vector<OccupiedBox> occupiedBoxes(const VoxelGrid& grid) {
  std::vector<OccupiedBox> boxes;
  for (int z = 0; z < grid.dims().z; ++z)
    for (int y = 0; y < grid.dims().y; ++y)
      for (int x = 0; x < grid.dims().x; ++x)
        if (grid.occupied({x, y, z})) {
          const Bounds3 b = grid.voxelBounds({x, y, z});
          boxes.push_back({{x, y, z}, glm::dvec3(b.lo), glm::dvec3(b.hi)});
        }
  return boxes;
}

// The brute-force answer for one ray: the earliest entry into an occupied voxel's shrunk box
// (t_solid: the walk must not pass it) and into any grown box (t_touch: the walk must not report
// anything before it).
struct Reference {
  double t_solid = kInf, t_touch = kInf;
};
Reference bruteForce(const std::vector<OccupiedBox>& boxes, const Ray& ray, float t_max, double eps) {
  Reference ref;
  for (const OccupiedBox& b : boxes) {
    const Contact c = contact(ray, b.lo, b.hi, t_max, eps);
    if (!c.inner.empty()) ref.t_solid = std::min(ref.t_solid, c.inner.t_in);
    if (!c.outer.empty()) ref.t_touch = std::min(ref.t_touch, c.outer.t_in);
  }
  return ref;
}

::testing::AssertionResult agreesWithReference(const VoxelGrid& grid, const Reference& ref, const Ray& ray,
                                               float t_max, const VoxelHit& hit, double eps) {
  if (!hit.hit()) {
    if (ref.t_solid < kInf)
      return ::testing::AssertionFailure() << "missed a voxel entered at t=" << ref.t_solid;
    return ::testing::AssertionSuccess();
  }
  if (!grid.occupied(hit.voxel)) return ::testing::AssertionFailure() << "reported an empty voxel";
  const Bounds3 vb = grid.voxelBounds(hit.voxel);
  const Contact own = contact(ray, glm::dvec3(vb.lo), glm::dvec3(vb.hi), t_max, eps);
  if (own.outer.empty()) return ::testing::AssertionFailure() << "reported voxel is not on the ray";
  // The walk's entry t lies between entering the grown box and entering the shrunk one (or
  // leaving the grown one, for a grazing contact).
  const double t_hi = own.inner.empty() ? own.outer.t_out : own.inner.t_in;
  const double t = hit.t;
  if (t < own.outer.t_in - eps || t > t_hi + eps)
    return ::testing::AssertionFailure()
           << "t=" << hit.t << " but the voxel is entered in [" << own.outer.t_in << ", " << t_hi << "]";
  if (t > ref.t_solid + eps)
    return ::testing::AssertionFailure() << "t=" << t << " skips a voxel entered at " << ref.t_solid;
  if (t < ref.t_touch - eps)
    return ::testing::AssertionFailure() << "t=" << t << " before any contact " << ref.t_touch;
  return ::testing::AssertionSuccess();
}

// A small grid (brute force stays cheap) with a clustered, sparse foreground and a partial brick.
VoxelGrid testGrid(unsigned seed, int brick_size) {
  VoxelGridSettings s;
  s.bounds = {vec3(-1.0f, 0.0f, -1.0f), vec3(1.0f, 1.8f, 1.0f)};
  s.voxel_size = 0.1f;  // 20 x 18 x 20
  s.brick_size = brick_size;
  VoxelGrid grid(s);
  ForegroundCloud cloud;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int blob = 0; blob < 4; ++blob) {
    const vec3 c(-0.8f + 1.6f * u(rng), 0.2f + 1.4f * u(rng), -0.8f + 1.6f * u(rng));
    for (int i = 0; i < 40; ++i) {
      ForegroundPoint p;
      p.position = c + 0.25f * vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 2.0f;
      cloud.points.push_back(p);
    }
  }
  grid.build(cloud);
  return grid;
}

// Adversarial rays: lattice origins (faces, edges, corners), axis-parallel and diagonal
// directions with signed zeros, tiny components, origins far outside, short t_max.
Ray adversarialRay(const VoxelGrid& grid, std::mt19937& rng, float& t_max) {
  std::uniform_int_distribution<int> pick(0, 9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const glm::ivec3 dims = grid.dims();
  auto lattice = [&](int a) {
    return grid.origin()[a] +
           grid.voxelSize() * float(std::uniform_int_distribution<int>(-2, dims[a] + 2)(rng));
  };
  Ray r;
  for (int a = 0; a < 3; ++a)
    r.origin[a] = pick(rng) < 6 ? lattice(a)
                                : grid.origin()[a] +
                                      grid.voxelSize() * (float(dims[a]) + 4.0f) * (u(rng) * 1.2f - 0.1f);
  vec3 d;
  const int kind = pick(rng);
  if (kind < 3) {  // axis-parallel, the other components +0.0 or -0.0
    d = vec3(pick(rng) < 5 ? 0.0f : -0.0f, pick(rng) < 5 ? 0.0f : -0.0f, pick(rng) < 5 ? 0.0f : -0.0f);
    d[kind] = pick(rng) < 5 ? 1.0f : -1.0f;
  } else if (kind < 5) {  // in a coordinate plane (one signed zero)
    d = vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f);
    d[kind - 3] = pick(rng) < 5 ? 0.0f : -0.0f;
  } else if (kind < 7) {  // exact diagonals through lattice corners
    d = vec3(pick(rng) < 5 ? 1.0f : -1.0f, pick(rng) < 5 ? 1.0f : -1.0f, pick(rng) < 5 ? 1.0f : -1.0f);
  } else if (kind < 8) {  // nearly axis-parallel: tiny (denormal-ish) components
    d = vec3(1e-30f * (u(rng) - 0.5f), 1e-20f * (u(rng) - 0.5f), 1.0f);
    std::shuffle(&d[0], &d[0] + 3, rng);
  } else {
    d = vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f);
  }
  if (d == vec3(0.0f)) d = vec3(0.0f, 1.0f, 0.0f);
  r.direction = glm::normalize(d);
  if (!isFinite(r.direction)) r.direction = vec3(0.0f, 0.0f, 1.0f);
  t_max = pick(rng) < 2 ? u(rng) * 1.5f : kInf;
  return r;
}

Ray randomRay(const VoxelGrid& grid, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> n(0.0f, 1.0f);
  const vec3 lo = grid.origin() - 0.5f, hi = grid.origin() + vec3(grid.dims()) * grid.voxelSize() + 0.5f;
  Ray r;
  r.origin = lo + (hi - lo) * vec3(u(rng), u(rng), u(rng));
  vec3 d(n(rng), n(rng), n(rng));
  r.direction = glm::length(d) > 1e-6f ? glm::normalize(d) : vec3(1.0f, 0.0f, 0.0f);
  return r;
}

TEST(VoxelWalk, MatchesBruteForceOnAMillionRays) {
  // 4 grids x 250k rays (half adversarial), both modes checked on every ray.
  std::size_t hits = 0, failures = 0;
  WalkStats stats;
  for (unsigned g = 0; g < 4; ++g) {
    const VoxelGrid grid = testGrid(100 + g, g % 2 == 0 ? 4 : 8);
    const std::vector<OccupiedBox> boxes = occupiedBoxes(grid);
    ASSERT_GT(boxes.size(), 20u);
    std::mt19937 rng(7 + g);
    const double eps = 1e-3 * grid.voxelSize();
    for (int i = 0; i < 250000; ++i) {
      float t_max = kInf;
      const Ray ray = (i % 2 == 0) ? adversarialRay(grid, rng, t_max) : randomRay(grid, rng);
      const VoxelHit skip = firstOccupiedVoxel(grid, ray, t_max, WalkMode::Skipping, &stats);
      const VoxelHit dense = firstOccupiedVoxel(grid, ray, t_max, WalkMode::Dense, &stats);
      hits += skip.hit() ? 1 : 0;
      const Reference ref = bruteForce(boxes, ray, t_max, eps);
      for (const VoxelHit* h : {&skip, &dense}) {
        const auto ok = agreesWithReference(grid, ref, ray, t_max, *h, eps);
        if (!ok && ++failures <= 10)
          ADD_FAILURE() << (h == &skip ? "skipping" : "dense") << " walk, grid " << g << " ray " << i
                        << " o=(" << ray.origin.x << "," << ray.origin.y << "," << ray.origin.z << ") d=("
                        << ray.direction.x << "," << ray.direction.y << "," << ray.direction.z
                        << ") t_max=" << t_max << ": " << ok.message();
      }
    }
  }
  EXPECT_EQ(failures, 0u);
  EXPECT_EQ(stats.capped, 0u);
  // The foreground is sparse but not negligible: a real fraction of rays hit it.
  EXPECT_GT(hits, 50000u);
  EXPECT_LT(hits, 800000u);
}

TEST(VoxelWalk, DegenerateRaysMissWithoutTrouble) {
  const VoxelGrid grid = testGrid(3, 4);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(firstOccupiedVoxel(grid, Ray{vec3(0.0f, 0.9f, 0.0f), vec3(0.0f)}).hit());
  EXPECT_FALSE(firstOccupiedVoxel(grid, Ray{vec3(nan), vec3(0.0f, 1.0f, 0.0f)}).hit());
  EXPECT_FALSE(firstOccupiedVoxel(grid, Ray{vec3(0.0f, 0.9f, 0.0f), vec3(kInf, 0, 0)}).hit());
  EXPECT_FALSE(firstOccupiedVoxel(grid, Ray{vec3(0.0f, 0.9f, 0.0f), vec3(1, 0, 0)}, nan).hit());
  EXPECT_FALSE(firstOccupiedVoxel(grid, Ray{vec3(0.0f, 0.9f, 0.0f), vec3(1, 0, 0)}, -1.0f).hit());
  // Far outside, pointing away.
  EXPECT_FALSE(firstOccupiedVoxel(grid, Ray{vec3(1e30f, 0.0f, 0.0f), vec3(1, 0, 0)}).hit());
}

TEST(VoxelWalk, EmptyAndFullGrids) {
  VoxelGridSettings s;
  s.bounds = {vec3(0.0f), vec3(1.0f)};
  s.voxel_size = 0.1f;
  VoxelGrid grid(s);
  const Ray inward{vec3(-0.5f, 0.55f, 0.55f), vec3(1.0f, 0.0f, 0.0f)};
  EXPECT_FALSE(firstOccupiedVoxel(grid, inward).hit());
  EXPECT_FALSE(firstOccupiedVoxel(grid, inward, kInf, WalkMode::Dense).hit());
  ForegroundCloud full;
  for (int z = 0; z < 10; ++z)
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 10; ++x) {
        ForegroundPoint p;
        p.position = (vec3(x, y, z) + 0.5f) * 0.1f;
        full.points.push_back(p);
      }
  grid.build(full);
  ASSERT_EQ(grid.occupiedCount(), 1000u);
  const VoxelHit h = firstOccupiedVoxel(grid, inward);
  ASSERT_TRUE(h.hit());
  EXPECT_EQ(h.voxel, glm::ivec3(0, 5, 5));
  EXPECT_NEAR(h.t, 0.5f, 1e-5f);
  // From inside, the origin's own voxel at t = 0.
  const VoxelHit inside = firstOccupiedVoxel(grid, Ray{vec3(0.33f, 0.47f, 0.91f), vec3(0, -1, 0)});
  ASSERT_TRUE(inside.hit());
  EXPECT_EQ(inside.voxel, glm::ivec3(3, 4, 9));
  EXPECT_EQ(inside.t, 0.0f);
}

}  // namespace
}  // namespace holo::reflect
