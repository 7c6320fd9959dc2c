#include "inside_glass.hpp"

#include <algorithm>
#include <cmath>

#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/optics.hpp"
#include "layer_inputs.hpp"
#include "relic_passage.hpp"
#include "sun_light.hpp"

namespace holo::reflect {
namespace {

// The lobe at which the hall's radiance weights each light direction: wide, so 16 directions
// sample it without picking out single lamps.
constexpr float kLightLobeRoughness = 0.6f;

}  // namespace

InsideGlassShading shadeInsideGlass(const RenderScene& scene, const PrefilteredIbl& ibl,
                                    const TracerSettings& settings, const SurfacePoint& surface,
                                    const vec3& direction) {
  InsideGlassShading out;
  // With the sun light, the sun is not left in the 9 coefficients (they spread a point-like light
  // over the whole sphere): the part is lit by the panorama without it, through the relic, plus
  // the sun along one shadow ray through the relic, as a hit point is.
  const bool sun_apart = settings.evaluation.sun_light && ibl.sun().found;
  const Frame frame(surface.normal);
  vec3 through(0.0f), free(0.0f);
  for (int k = 0; k < kLightDirections; ++k) {
    // Cosine-spread: a Fibonacci spiral over the unit disc, lifted onto the hemisphere.
    const float r = std::sqrt((float(k) + 0.5f) / float(kLightDirections));
    const float phi = float(k) * 2.39996323f;
    const vec3 local(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - r * r)));
    const vec3 d = frame.toWorld(local);
    vec3 hall = ibl.seenFrom(surface.position, d, kLightLobeRoughness);
    if (sun_apart)
      hall = glm::max(hall - ibl.sunSeenFrom(surface.position, d, kLightLobeRoughness), vec3(0.0f));
    free += hall;
    through += hall * passedThroughRelic(scene, settings, surface.position, d, out.rays, InterfaceLoss::None);
  }
  vec3 irradiance = sun_apart ? ibl.irradianceWithoutSun(surface.normal) : ibl.irradiance(surface.normal);
  for (int c = 0; c < 3; ++c) irradiance[c] *= free[c] > 0.0f ? through[c] / free[c] : 0.0f;
  if (sun_apart && readsSunIrradiance(surface.material))
    irradiance += SunLight(scene, ibl, settings).irradiance(surface, -direction, out.rays);
  out.shading = ibl.shadeParts(surface.material, surface.normal, -direction,
                               glm::reflect(direction, surface.normal), surface.position, &irradiance);
  // The emission is the part's own: the occlusion and the light through the relic scale the rest.
  out.shading.specular_scale *= surface.occlusion;
  out.shading.diffuse = surface.occlusion * out.shading.diffuse + surface.emission;
  out.shading.specular_scale *= passedThroughRelic(scene, settings, surface.position,
                                                   glm::reflect(direction, surface.normal), out.rays);
  return out;
}

}  // namespace holo::reflect
