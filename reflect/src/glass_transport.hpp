// Glass transport (internal): the light transmitted at a hit point of a transmissive relic material
// (KHR_materials_transmission, _volume, _ior) traced through the relic, for the refraction pass
// (refraction_pass.hpp), the internal-depth probe (internal_depth.hpp) and the glass a secondary
// ray meets (static_shading.hpp's shadeMet).
//
// At a hit point of a transmissive material the light splits by the exact unpolarised Fresnel
// reflectance F of its IOR (optics.hpp): F goes to the reflection (the specular scale the
// composition already blends with the visitors), (1 - F) (1 - metallic) transmission base_colour
// enters the relic. The transmitted path is traced with Embree through the relic, one ray per
// interface event (entering, leaving, a total internal reflection), up to `depth` events:
//  * entering from outside: Snell refraction, F of it reflected back out, the rest tinted by
//    base_colour (glTF's specular BTDF);
//  * leaving: where F = 1 (total internal reflection) the path reflects and goes on. Otherwise the
//    refracted (1 - F) leaves (the interface alone: a volume tints where light enters, as the
//    path tracer's glass), and the light that partly reflects inside is followed where it is
//    at least TracerSettings::refraction_branch_weight of the light entering and the path's
//    refraction_branch_rays last: it bounces on inside, each of its exits reading the
//    prefiltered IBL along its refracted ray into `resolved` (a crystal's facets send it out in
//    many directions). Where they stop it, it is summed in closed form as between two parallel
//    walls with the same F and the last segment's absorption a: (1 - F) / (1 - F^2 a^2) leaves
//    along the refracted ray, F a (1 - F) / (1 - F^2 a^2) leaves back towards the side it came
//    from. Exact for a slab; everywhere energy is kept, never invented. What the main path sends
//    back (this, and what a later wall sends back out of its entry face) joins the entry's
//    reflection weight, its hall and its visitors: between parallel walls it leaves along the
//    entry's mirror direction, and it costs no lookup; a followed branch's leaves through the face
//    it last reflected from. F at a later entry leaves along that face's own mirror direction,
//    read there through the relic (relic_passage.hpp, no Fresnel loss): a bowl's back wall seen
//    from inside shows the sky its concave face turns to;
//  * every interface met reads its material as a hit point does (resolveSurface: its textures,
//    its mapped normal); an opaque one (no transmitted share: a candle inside a hurricane glass)
//    ends the path, shaded as a hit point with the hall's light through the relic
//    (inside_glass.hpp), its specular lobe the exit ray (its visitors walked);
//  * inside a volume (thickness > 0), Beer-Lambert absorption over each segment's length with
//    sigma = -ln(attenuation_colour) / attenuation_distance (optics.hpp: a channel of colour 0
//    is fully absorbed); thin-walled materials (thickness 0) pass light straight through, unbent;
//  * the light not transmitted where a later interface is entered ((1 - transmission) of a partly
//    transmissive material) is lit by the IBL's irradiance as a Lambert surface.
// The path that leaves the relic reads the prefiltered IBL at the transmitted lobe's width (every
// IBL read of transmitted light through the panorama's proxy from where the light leaves, the
// hall's parallax as the static shading has it): each rough refraction widens it by GGX alpha
// |ior - 1| / 2 (in quadrature, times transmitted_roughness_scale), each rough internal reflection
// by alpha. At the depth cap the energy still inside goes to the IBL along the last direction.
#pragma once

#include <cstdint>
#include <vector>

#include "holo/reflect/foreground_camera_image.hpp"
#include "holo/reflect/frame_result.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/tracer_settings.hpp"

namespace holo::reflect {

// A transmitted path from a hit point through the relic.
struct TransmittedPath {
  vec3 scale{0.0f};        // radiance factor of what the exit ray sees
  vec3 environment{0.0f};  // the prefiltered IBL along the exit ray at the lobe's width
  vec3 resolved{0.0f};     // radiance already read from the IBL on the way (untransmitted light,
                           // the cap's remainder)
  vec3 reflected{0.0f};    // weight of the light sent back towards the viewer's side (reflected
                           // at a later interface, or inside and out again): joins the entry's
                           // reflection (its environment and its visitors)
  vec3 exit_position{0.0f}, exit_direction{0.0f, 0.0f, 1.0f};
  float roughness = 0.0f;  // of the transmitted lobe at the exit (perceptual)
  vec3 entry{0.0f};        // weight of the light entering at the first event: (1 - F)(1 - metallic)
                           // transmission base_colour; scale, resolved and reflected include it
  bool exited = false;     // the path left the relic before the cap (its exit ray can be walked)
  int events = 0;          // interface events followed
  std::uint32_t rays = 0;  // Embree rays cast
};

// Traces the light entering at `position` (shading normal `normal` on the viewer's side) along
// `direction` (into the surface) through the relic, the entry's Fresnel and transmission weight
// included; entry_textured (optional): the entry's base colour, metallic, roughness, transmission and
// thickness as the hit point sampled them from textures (every later hit reads its own textures too;
// without it the entry reads the factors). `alive` (optional, kMaxInternalDepth + 1 entries) gets the
// RGB energy still being followed after each event count added.
TransmittedPath traceTransmission(const RenderScene& scene, const PrefilteredIbl& ibl,
                                  const TracerSettings& settings, int depth, const vec3& position,
                                  const vec3& normal, const vec3& direction, const Material& material,
                                  const SurfaceMaterial* entry_textured = nullptr,
                                  std::vector<glm::dvec3>* alive = nullptr);

// traceTransmission per unit of light entering: path.entry is set, but scale, resolved and
// reflected leave it out, for the caller to multiply in (applyEntry), or a neighbour's own (a
// sample that blends the anchors' paths, refraction_anchors.hpp).
TransmittedPath traceTransmissionPerUnitEntry(const RenderScene& scene, const PrefilteredIbl& ibl,
                                              const TracerSettings& settings, int depth, const vec3& position,
                                              const vec3& normal, const vec3& direction,
                                              const Material& material, const SurfaceMaterial* entry_textured,
                                              std::vector<glm::dvec3>* alive);

// The weight path.entry of light entering along `direction` at a surface of shading normal
// `normal` (the first event of traceTransmissionPerUnitEntry).
vec3 entryWeight(const vec3& normal, const vec3& direction, const Material& m,
                 const SurfaceMaterial* textured);

// Multiplies path.entry into a path per unit entry's scale, resolved and reflected.
void applyEntry(TransmittedPath& path);

// The light a ray along `direction` that meets the relic's transmissive `surface` receives through
// it: the transmitted path traced (bent at each interface, what stands inside shaded as a hit point
// is, up to settings.refraction_depth events, kMaxInternalDepth where it is measured) with the
// light it sends back towards the ray's side read along the entry's mirror direction; the entry's
// own Fresnel reflection is left to the caller. For a lobe's ray that meets glass (a metal foot
// below a thick glass bottom sees the light that bottom bends and guides, and the candle in it).
// `rays` gets the Embree rays cast.
vec3 lightThroughGlass(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                       const SurfacePoint& surface, const vec3& direction, std::uint64_t& rays);

}  // namespace holo::reflect
