#include "inside_glass.hpp"

#include <algorithm>
#include <cmath>

#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/optics.hpp"
#include "layer_inputs.hpp"

namespace holo::reflect {
namespace {

// Interfaces a light ray crosses before it is counted as stopped (glass walls come in pairs).
constexpr int kMaxCrossings = 8;
// The lobe at which the hall's radiance weights each light direction: wide, so 16 directions
// sample it without picking out single lamps.
constexpr float kLightLobeRoughness = 0.6f;

// What the relic passes of the hall's light arriving at `origin` from `direction` (RGB in
// [0, 1]); `rays` counts the Embree rays.
vec3 passedThroughRelic(const RenderScene& scene, const TracerSettings& settings, const vec3& origin,
                        const vec3& direction, std::uint32_t& rays) {
  const RayScene& relic = scene.relicOnly();
  const float offset = std::max(settings.ray_offset, 1e-5f);
  vec3 passed(1.0f), sigma(0.0f), position = origin;
  bool inside = false;
  for (int crossing = 0; crossing < kMaxCrossings; ++crossing) {
    const Ray ray{position, direction};
    const RayHit hit = relic.intersect(ray, offset);
    ++rays;
    if (!hit.hit()) return passed;
    if (inside) passed *= transmittance(sigma, hit.t);
    const SurfacePoint s = resolveSurface(scene, relic, ray, hit, 0.0f);
    const SurfaceMaterial& m = s.material;
    const float share = (1.0f - clamp01(m.metallic)) * clamp01(m.transmission);
    if (!(share > 0.0f) || !isFinite(s.position)) return vec3(0.0f);
    const float cos_i = std::clamp(std::abs(glm::dot(s.geometric_normal, direction)), 1e-6f, 1.0f);
    const float ior = safeIor(m.ior);
    const float fresnel = std::min(fresnelDielectric(cos_i, inside ? 1.0f / ior : ior), 1.0f);
    // Entering (or a thin wall) passes the material's share and tint; leaving, the interface alone.
    if (inside)
      passed *= 1.0f - fresnel;
    else
      passed *= (1.0f - fresnel) * share * glm::clamp(m.base_colour, vec3(0.0f), vec3(1.0f));
    if (!m.thin_walled) {
      inside = !inside;
      sigma = inside ? attenuationCoefficient(m.attenuation_colour, m.attenuation_distance) : vec3(0.0f);
    }
    position = s.position;
    if (!(maxComponent(passed) > 1e-4f)) return vec3(0.0f);
  }
  return vec3(0.0f);
}

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
    through += hall * passedThroughRelic(scene, settings, surface.position, d, out.rays);
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
