#include "internal_depth.hpp"

#include <algorithm>
#include <cmath>

#include "holo/core/fibonacci_sphere.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/surface_shading.hpp"

namespace holo::reflect {

InternalDepth measureInternalDepth(const RenderScene& scene, const PrefilteredIbl& ibl,
                                   const TracerSettings& settings, float residual_limit) {
  InternalDepth result;
  result.left.assign(kMaxInternalDepth + 1, 0.0);
  const Bounds3 box = scene.relicBounds();
  if (box.empty()) return result;
  const vec3 centre = 0.5f * (box.lo + box.hi);
  const float radius = 0.5f * glm::length(box.hi - box.lo);
  const RayScene& relic = scene.relicOnly();
  // Fibonacci sphere of viewing directions, each aimed at a point of a disc across the relic
  // (R2 low-discrepancy offsets): deterministic, even over directions and over the relic.
  constexpr int kProbes = 1024;
  // Traced one event past the largest depth, so the share still inside at that depth is known.
  std::vector<glm::dvec3> alive(kMaxInternalDepth + 1, glm::dvec3(0.0));
  for (int i = 0; i < kProbes; ++i) {
    const vec3 dir = fibonacciDirection(i, kProbes);
    const Frame frame(dir);
    const float u = std::fmod(0.5f + 0.7548777f * float(i), 1.0f),
                v = std::fmod(0.5f + 0.5698403f * float(i), 1.0f);
    const float disc_r = 0.8f * radius * std::sqrt(u), phi = 2.0f * kPi * v;
    const vec3 target = centre + disc_r * (std::cos(phi) * frame.t + std::sin(phi) * frame.b);
    const Ray ray{target + 2.0f * radius * dir, -dir};
    const RayHit hit = relic.intersect(ray);
    if (!hit.hit()) continue;
    const Material& m = scene.relicGltfMaterial(hit, relic);
    if (!(m.transmission > 0.0f)) continue;
    ++result.probes_hit;
    // The entry's textures read as a hit point reads them (a texture may make the glass clear).
    const SurfacePoint surface = resolveSurface(scene, relic, ray, hit, 0.0f);
    traceTransmission(scene, ibl, settings, kMaxInternalDepth + 1, surface.position, surface.normal,
                      ray.direction, m, &surface.material, &alive);
  }
  // Per RGB channel, the largest share left: a volume that absorbs red and green leaves blue light
  // bouncing long after the luminance is gone (the Khronos hurricane glass's thick bottom).
  if (!(std::max({alive[0].x, alive[0].y, alive[0].z}) > 0.0)) return result;
  for (int k = 0; k <= kMaxInternalDepth; ++k) {
    double left = 0.0;
    for (int c = 0; c < 3; ++c)
      if (alive[0][c] > 0.0) left = std::max(left, alive[std::size_t(k)][c] / alive[0][c]);
    result.left[std::size_t(k)] = left;
  }
  result.depth = kMaxInternalDepth;
  for (int k = 1; k <= kMaxInternalDepth; ++k)
    if (result.left[std::size_t(k)] < double(residual_limit)) {
      result.depth = k;
      break;
    }
  result.residual = float(result.left[std::size_t(result.depth)]);
  return result;
}

}  // namespace holo::reflect
