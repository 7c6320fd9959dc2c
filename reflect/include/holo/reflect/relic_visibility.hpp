// The relic's self-occlusion under the hall's light, precomputed per vertex when the relic is
// loaded (visibility under prefiltered lighting, filtered importance sampling Section 5.2, in
// the per-vertex transfer form of precomputed radiance transfer): per vertex and side of each
// relic mesh, the transfer T, 9 RGB spherical-harmonic coefficients (irradiance_sh.hpp's
// basis) with which the environment's radiance coefficients L, in the relic's frame, give the
// irradiance that reaches the vertex, E = sum_i T_i L_i (RGB products, clamped at 0):
//  * the clamped cosine over the directions the relic leaves open: the unoccluded transfer
//    kCosineLobe_i Y_i(n) minus pi / N sum Y_i(w) over the occluded ones of N stratified
//    cosine-distributed rays (those that meet the relic);
//  * plus the light its own diffuse surfaces pass on, `bounces` times: an occluded ray adds
//    albedo(hit) T(hit) / N, T(hit) interpolated from the hit triangle's vertices, the albedo
//    the hit's diffuse one ((1 - metallic)(1 - transmission) base colour (1 - its strongest F0)).
// A convex relic has nothing to occlude: the frame renderer builds none for it (effect_plan.hpp).
// The rays are a fixed stratified pattern per vertex, its offset hashed from the vertex, so the
// result is the same on every run and thread count.
// Units: radiance coefficients in, irradiance out; metres.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/surface_shading.hpp"

namespace holo::reflect {

struct RelicVisibilitySettings {
  int rays_per_vertex = 64;  // per vertex and side, a square number 4..4096 (side x side strata)
  int bounces = 2;           // diffuse interreflection bounces folded in, 0..8 (0: visibility only)
  float ray_offset = 1e-3f;  // metres a ray starts along the vertex normal, against self-hits
};

class RelicVisibility {
 public:
  // `scene` must outlive this. Casts (1 + bounces) x rays_per_vertex rays per vertex and side against
  // scene.relicOnly() (both sides for a double-sided material, the front alone otherwise). Throws InputError
  // on invalid settings.
  RelicVisibility(const RenderScene& scene, const RelicVisibilitySettings& settings = {});

  // Whether `at` has a transfer (a located point on a side that was computed).
  bool covers(const SurfaceLocation& at) const;
  // The irradiance at `at` (covers(at)) under radiance coefficients `radiance` in the relic's
  // frame (PrefilteredIbl::relicFrameRadiance).
  vec3 irradiance(const SurfaceLocation& at, const std::array<vec3, 9>& radiance) const;
  // The cosine-weighted share of the hemisphere at `at` (covers(at)) the relic leaves open, [0, 1].
  float openness(const SurfaceLocation& at) const;

  std::uint64_t rays() const { return rays_; }               // rays cast to build it
  std::size_t vertexSides() const { return vertex_sides_; }  // transfers computed
  float maxOcclusion() const { return max_occlusion_; }      // largest 1 - openness of a vertex
  float meanOcclusion() const { return mean_occlusion_; }    // mean 1 - openness over them

 private:
  struct Transfer {
    std::array<vec3, 9> t{};
    float open = 1.0f;
  };
  // The transfers of a location's triangle corners on its side, with their barycentric weights.
  struct Corners {
    std::array<const Transfer*, 3> vertex;
    std::array<float, 3> weight;
  };
  Corners corners(const SurfaceLocation& at) const;
  const Model* model_;
  // Per mesh, per side (0 front, 1 back), per vertex; a side not computed is empty.
  std::vector<std::array<std::vector<Transfer>, 2>> transfers_;
  std::uint64_t rays_ = 0;
  std::size_t vertex_sides_ = 0;
  float max_occlusion_ = 0.0f, mean_occlusion_ = 0.0f;
};

}  // namespace holo::reflect
