// What a ray hit on the relic looks like to a renderer: its glTF material resolved at the point
// (every texture slot read through its texCoord set, KHR_texture_transform and sampler, filtered
// at the mip level of the ray's footprint), the normal-mapped shading normal, the occlusion, the
// emission and the opacity. The one place that turns a hit + holo::Material into shading
// parameters: the path tracer (ground truth), the live renderer's static shading and the IBL
// baseline all call it, so they render the same material.
//
// Conventions (glTF 2.0):
//  * base colour = baseColorFactor x sRGB-decoded texture; alpha = factor A x texture A;
//  * roughness x texture G, metallic x texture B (metallicRoughnessTexture);
//  * specular = factor x specularTexture A; specular colour = factor x sRGB-decoded
//    specularColorTexture RGB (KHR_materials_specular), the dielectric's F0 with the IOR
//    (bsdf.hpp's dielectricF0);
//  * occlusion = 1 + strength (R - 1): it scales every reflected term, never the emission. Our
//    scenes have no punctual lights (the hall, the visitors and the sky reach the relic as
//    image-based or emitted light, which glTF counts as indirect), so in both renderers all
//    reflected light is indirect;
//  * emission = emissiveFactor x KHR_materials_emissive_strength x sRGB-decoded texture;
//  * normal map: n = normalize(T x s + B y s + N z) with (x, y, z) = 2 texel - 1, s = scale,
//    B = w cross(N, T), T and w from the mesh's tangents (generated MikkTSpace-style by the
//    RenderScene when a normal-mapped mesh has none);
//  * a back face of a double-sided material is shaded with the reversed normal; a back face of a
//    single-sided opaque material is culled (reflect/src/surface_opacity.hpp), transmissive ones are not (a
//    ray inside glass must leave it);
//  * alphaMode MASK: opacity 1 where alpha >= alphaCutoff, else 0 (the ray passes); BLEND:
//    opacity = alpha; OPAQUE: 1 whatever the alpha.
// Footprint: `cone_width` is the width in metres of the ray's pixel footprint at the hit measured
// across the ray (distance x angular pixel size); divided by the cosine of incidence (at most
// 1/kMinFootprintCosine) and multiplied by the triangle's uv units per metre it is the uv
// footprint holo::sampleTexture picks the mip level from. 0: the sharpest level.
#pragma once

#include <cstdint>

#include "holo/core/ray_scene.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reflect {

inline constexpr float kMinFootprintCosine = 0.2f;

// Where on the relic's mesh a surface point lies: what per-vertex data (relic_visibility.hpp) is
// interpolated with.
struct SurfaceLocation {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::uint32_t mesh = kNone;  // index into the relic's meshes; kNone: not located
  std::uint32_t triangle = 0;
  vec2 barycentric{0.0f};  // Embree's (u, v) on the triangle
  bool front = true;       // seen from the side its winding's normal points to
  bool located() const { return mesh != kNone; }
};

struct SurfacePoint {
  vec3 position{0.0f};
  vec3 normal{0.0f, 1.0f, 0.0f};            // unit shading normal (normal-mapped), viewer's side
  vec3 geometric_normal{0.0f, 1.0f, 0.0f};  // unit, viewer's side
  vec3 clearcoat_normal{0.0f, 1.0f, 0.0f};  // unit, viewer's side: the coat's own normal map, else normal
  SurfaceMaterial material;
  vec3 emission{0.0f};         // radiance emitted towards the viewer, >= 0, finite
  float occlusion = 1.0f;      // [0,1], scales reflected light only
  float alpha = 1.0f;          // [0,1] BLEND coverage (1 for OPAQUE and MASK)
  bool normal_mapped = false;  // the normal comes from a normal map (it may lean past the face)
  SurfaceLocation location;
};

// The relic's surface where `ray` hit it in `traced` (relicOnly() or all(); hit on the relic).
// Finite whatever the mesh: degenerate uvs or tangents fall back to a frame around the normal.
SurfacePoint resolveSurface(const RenderScene& scene, const RayScene& traced, const Ray& ray,
                            const RayHit& hit, float cone_width);

// The split-sum IBL shading of a surface point seen from wo: occlusion scales the specular and
// diffuse parts, the emission is added to the diffuse part (so it is never occluded and the
// composition, specular_scale x L + diffuse, carries it).
SplitSumShading shadeSurface(const PrefilteredIbl& ibl, const SurfacePoint& surface, const vec3& wo);

}  // namespace holo::reflect
