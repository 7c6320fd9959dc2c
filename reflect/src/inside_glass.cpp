#include "inside_glass.hpp"

#include <algorithm>
#include <cmath>

#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/optics.hpp"
#include "layer_inputs.hpp"
#include "relic_passage.hpp"

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
  out.shading = shadeSurface(ibl, surface, -direction);
  const Frame frame(surface.normal);
  vec3 through(0.0f), free(0.0f);
  for (int k = 0; k < kLightDirections; ++k) {
    // Cosine-spread: a Fibonacci spiral over the unit disc, lifted onto the hemisphere.
    const float r = std::sqrt((float(k) + 0.5f) / float(kLightDirections));
    const float phi = float(k) * 2.39996323f;
    const vec3 local(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - r * r)));
    const vec3 d = frame.toWorld(local);
    const vec3 hall = ibl.seenFrom(surface.position, d, kLightLobeRoughness);
    free += hall;
    through += hall * passedThroughRelic(scene, settings, surface.position, d, out.rays, InterfaceLoss::None);
  }
  vec3 diffuse_scale(0.0f);
  for (int c = 0; c < 3; ++c) diffuse_scale[c] = free[c] > 0.0f ? through[c] / free[c] : 0.0f;
  // The emission is the part's own: the hall's light through the relic scales the rest.
  const vec3 reflected_light = out.shading.diffuse - surface.emission;
  out.shading.diffuse = reflected_light * diffuse_scale + surface.emission;
  out.shading.specular_scale *= passedThroughRelic(scene, settings, surface.position,
                                                   glm::reflect(direction, surface.normal), out.rays);
  return out;
}

}  // namespace holo::reflect
