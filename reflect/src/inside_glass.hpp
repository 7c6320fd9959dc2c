// What stands inside the glass (internal): an opaque part of the relic that a transmitted path
// meets (a candle in a hurricane glass, flowers in a vase), for the glass transport
// (glass_transport.hpp). It is shaded as a hit point of the static shading is (its textures,
// occlusion and emission, the split-sum IBL), except that the hall's light reaches it through the
// relic: kLightDirections cosine-spread directions around its normal, and its mirror direction,
// are followed straight through the relic (a shadow ray's path: not bent), each entry into a
// transmissive material passing (1 - metallic) transmission base_colour of the light (as the path
// tracer's glass: tinted where the light enters), each volume segment its Beer-Lambert share, an
// opaque part nothing; the spread directions without the walls' Fresnel loss (what a wall reflects
// out of a wide lobe it reflects in: relic_passage.hpp), the mirror direction with it. The diffuse
// irradiance is scaled per RGB channel by the hall-weighted mean of what the directions pass (the
// hall's radiance along each at a wide lobe), the specular by what the mirror direction passes.
// With TracerEvaluationKnobs::sun_light and a sun in the panorama, a diffuse part is lit as a hit
// point of the static shading is: the panorama without its sun (its irradiance, and the hall that
// weights the directions) plus the sun as a directional light along one shadow ray through the
// relic (sun_light.hpp, the walls' Fresnel loss kept: one direction), not the sun spread over the
// 9 coefficients and the whole hemisphere.
#pragma once

#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/tracer_settings.hpp"

namespace holo::reflect {

inline constexpr int kLightDirections = 16;

struct InsideGlassShading {
  SplitSumShading shading;  // diffuse (occlusion, emission, light through the relic), specular
                            // scale (times what the mirror direction passes) and its environment
  std::uint32_t rays = 0;   // Embree rays cast
};

// `surface`: the opaque part as resolveSurface gives it, its normal towards `direction`'s origin;
// `direction`: the transmitted ray that met it.
InsideGlassShading shadeInsideGlass(const RenderScene& scene, const PrefilteredIbl& ibl,
                                    const TracerSettings& settings, const SurfacePoint& surface,
                                    const vec3& direction);

}  // namespace holo::reflect
