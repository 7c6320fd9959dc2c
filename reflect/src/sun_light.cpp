#include "sun_light.hpp"

#include <algorithm>

#include "relic_passage.hpp"

namespace holo::reflect {

SunLight::SunLight(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings)
    : scene_(scene),
      settings_(settings),
      direction_(ibl.relicFrameSunDirection()),
      power_(ibl.sun().found ? ibl.sun().power : vec3(0.0f)) {}

vec3 SunLight::irradiance(const SurfacePoint& surface, const vec3& to_viewer, std::uint32_t& rays) const {
  const float cosine = glm::dot(surface.normal, direction_);
  if (!(cosine > 0.0f) || !(maxComponent(power_) > 0.0f)) return vec3(0.0f);
  // The face the point lies on, on the viewer's side: a sun behind it is behind the relic's own
  // wall, and the ray leaves from its lit side.
  vec3 face = surface.normal;
  if (surface.location.located()) {
    const TriangleMesh& mesh = scene_.relic().meshes[surface.location.mesh];
    const uvec3 t = mesh.triangles[surface.location.triangle];
    const vec3 g =
        glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
    if (glm::dot(g, g) > 0.0f) face = glm::normalize(glm::dot(g, to_viewer) < 0.0f ? -g : g);
  }
  if (!(glm::dot(face, direction_) > 0.0f)) return vec3(0.0f);
  const vec3 origin = surface.position + face * settings_.ray_offset;
  return power_ * cosine * passedThroughRelic(scene_, settings_, origin, direction_, rays);
}

}  // namespace holo::reflect
