#include "relic_passage.hpp"

#include <algorithm>
#include <cmath>

#include "holo/reflect/optics.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "layer_inputs.hpp"

namespace holo::reflect {

vec3 passedThroughRelic(const RenderScene& scene, const TracerSettings& settings, const vec3& origin,
                        const vec3& direction, std::uint32_t& rays, InterfaceLoss loss) {
  const RayScene& relic = scene.relicOnly();
  const float offset = std::max(settings.ray_offset, 1e-5f);
  vec3 passed(1.0f), sigma(0.0f), position = origin;
  bool inside = false;
  for (int crossing = 0; crossing < kMaxRelicCrossings; ++crossing) {
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
    const float fresnel = loss == InterfaceLoss::Fresnel
                              ? std::min(fresnelDielectric(cos_i, inside ? 1.0f / ior : ior), 1.0f)
                              : 0.0f;
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

}  // namespace holo::reflect
