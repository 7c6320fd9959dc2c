// The relic's self-occlusion under the hall's light, precomputed per vertex when the relic is
// loaded: visibility under prefiltered lighting (filtered importance sampling, Section 5.2), its
// interreflection in the per-vertex transfer form of precomputed radiance transfer. Per vertex
// and side of each relic mesh, N stratified cosine-distributed rays (N <= 256, a square) are cast
// against the relic once; each vertex side keeps
//  * which strata are open (a bit mask): lit(), for one environment, sums over the open strata
//    the prefiltered environment along the stratum's direction, read at the roughness whose lobe
//    covers the stratum's solid angle (pi / (N cos theta), the FIS rule), times pi / N;
//  * the interreflection transfer B, 9 RGB spherical-harmonic coefficients (irradiance_sh.hpp's
//    basis) with which the environment's radiance coefficients L in the relic's frame give the
//    light the relic's own diffuse surfaces pass on, sum_i B_i L_i: an occluded ray adds
//    albedo(hit) T(hit) / N, T the transfer of the whole irradiance (the open strata's clamped
//    cosine, kCosineLobe_i Y_i(n) minus pi / N Y_i(w) of each occluded one, plus B), iterated
//    `bounces` times, T(hit) interpolated from the hit triangle's vertices, the albedo the hit's
//    diffuse one ((1 - metallic)(1 - transmission) base colour (1 - its strongest F0)).
// A triangle long against the relic (a backdrop of two triangles) gets a lattice of points with
// their own transfers, as vertices have (addLattices). The irradiance of a surface point is its
// triangle's vertices' irradiance (or its lattice cell's points'), interpolated. A
// convex relic has nothing to occlude: the frame renderer builds none for it (effect_plan.hpp).
// The rays are a fixed pattern per vertex, its jitter hashed from the vertex, so the result is
// the same on every run and thread count.
// Units: radiance in, irradiance out; metres.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/surface_shading.hpp"

namespace holo::reflect {

struct RelicVisibilitySettings {
  int rays_per_vertex = 256;  // per vertex and side, a square number 4..256 (side x side strata)
  int bounces = 4;            // diffuse interreflection bounces folded in, 0..8 (0: visibility only)
  float ray_offset = 1e-3f;   // metres a ray starts along the vertex normal, against self-hits
  // A triangle longer than the relic's diagonal / lattice_steps_per_relic gets a lattice of points
  // at that spacing (at most 32 segments a side), each with its own transfer; 0: vertices only.
  float lattice_steps_per_relic = 24.0f;  // 0..64
};

class RelicVisibility {
 public:
  // `scene` must outlive this. Casts (1 + bounces) x rays_per_vertex rays per vertex and side
  // against scene.relicOnly() (both sides for a double-sided or transmissive material, the front
  // alone otherwise). Throws InputError on invalid settings.
  RelicVisibility(const RenderScene& scene, const RelicVisibilitySettings& settings = {});

  // The irradiance of every vertex side under one environment (lit()).
  struct Lighting {
    std::vector<std::array<std::vector<vec3>, 2>> irradiance;  // per mesh, side, vertex
    bool without_sun = false;  // the panorama's sun left out of the open strata (lit())
  };
  // Lights every vertex side with `ibl` (its relic turn included). `filtered`: a prefiltered
  // lookup per open stratum plus the interreflection transfer; else the whole transfer T under
  // the radiance coefficients alone (9 products a vertex, cheap enough for every frame of a
  // turning relic; the shadows' detail of the 9 coefficients only).
  // `without_sun`: the ibl's sun (panorama_sun.hpp) left out of what the open strata see (its
  // point-light lobe taken off each filtered lookup; its SH off the transfer's direct part), for a
  // renderer that adds it with a shadow ray; its light passed on by the relic's own surfaces stays.
  Lighting lit(const PrefilteredIbl& ibl, bool filtered = true, bool without_sun = false) const;
  // What `lighting` changes on the display, in sRGB codes: over every vertex side, the largest
  // channel's difference between its diffuse radiance (the material's diffuse albedo / pi, its
  // factors alone: a texture only darkens) under lighting and under the unoccluded irradiance
  // (ibl.irradiance of its normal; irradianceWithoutSun where lighting is without the sun, whose
  // shadow the sun light casts), each tone-mapped at `exposure` (tone_map.hpp; <= 0: the one
  // autoExposure would choose for the relic's vertices so lit). The gloss a display adds over
  // the diffuse only lessens a difference, so this bounds it from above.
  float largestDisplayedChange(const Lighting& lighting, const PrefilteredIbl& ibl, float exposure) const;

  // Whether `at` has a transfer (a located point on a side that was computed).
  bool covers(const SurfaceLocation& at) const;
  // The irradiance at `at` (covers(at)) under `lighting` (lit() of this visibility).
  vec3 irradiance(const Lighting& lighting, const SurfaceLocation& at) const;
  // The cosine-weighted share of the hemisphere at `at` (covers(at)) the relic leaves open, [0, 1].
  float openness(const SurfaceLocation& at) const;

  std::uint64_t rays() const { return rays_; }               // rays cast to build it
  std::size_t vertexSides() const { return vertex_sides_; }  // transfers computed
  float maxOcclusion() const { return max_occlusion_; }      // largest 1 - openness of a vertex
  float meanOcclusion() const { return mean_occlusion_; }    // mean 1 - openness over them

 private:
  struct Transfer {
    std::array<vec3, 9> whole{};                 // T: the irradiance's transfer (what a bounce reads)
    std::array<vec3, 9> bounce{};                // B: its interreflection part
    std::array<std::uint64_t, 4> open_strata{};  // bit k: stratum k is open
    float open = 1.0f;
  };
  struct VertexSide {
    std::uint32_t mesh, vertex, side;
  };
  // The k-th ray of a vertex side: stratum (k % side, k / side) of the cosine-distributed
  // hemisphere, its offset within the stratum hashed from the vertex side.
  Ray ray(const VertexSide& v, int k) const;
  // The corners of a location's triangle and their barycentric weights.
  struct Corners {
    uvec3 vertex;
    std::array<float, 3> weight;
  };
  Corners corners(const SurfaceLocation& at) const;
  // The lattice of a triangle longer than settings.lattice_steps_per_relic allows, so its
  // irradiance varies across it (a backdrop of two triangles under the relic's shadow); its points
  // are appended after the mesh's vertices.
  static constexpr int kMaxLatticeSteps = 32;
  struct Lattice {
    std::uint32_t first = 0;  // the index of its point (0, 0) among the mesh's points
    int steps = 0;            // 0: the triangle interpolates its own vertices
  };
  void addLattices(std::size_t mesh, const Bounds3& relic_box, float steps_per_relic);

  const Model* model_;
  int side_ = 8;
  float ray_offset_ = 1e-3f;
  std::vector<std::vector<vec3>> normals_;      // per mesh and point, unit normals (0: none)
  std::vector<std::vector<vec3>> positions_;    // per mesh: its vertices, then its lattices' points
  std::vector<std::vector<Lattice>> lattices_;  // per mesh and triangle; empty: none has one
  // Per mesh, per side (0 front, 1 back), per vertex; a side not computed is empty.
  std::vector<std::array<std::vector<Transfer>, 2>> transfers_;
  std::vector<VertexSide> vertex_sides_list_;
  std::uint64_t rays_ = 0;
  std::size_t vertex_sides_ = 0;
  float max_occlusion_ = 0.0f, mean_occlusion_ = 0.0f;
};

}  // namespace holo::reflect
