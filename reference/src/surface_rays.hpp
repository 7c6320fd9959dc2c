// Rays leaving a surface hit, shared by the path tracer and the caustic photon tracer so that
// both offset and orient their rays alike (the caustic is compared against the path tracer's own
// glass).
#pragma once

#include <algorithm>
#include <cmath>

#include "holo/core/ray_scene.hpp"

namespace holo::reference {

// Offset along the geometric normal, scaled with the magnitude of the position (float ulps).
inline Ray spawnRay(const vec3& p, const vec3& geometric_normal, const vec3& direction) {
  const float eps = 1e-4f * (1.0f + std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
  const float side = glm::dot(direction, geometric_normal) >= 0.0f ? 1.0f : -1.0f;
  return {p + side * eps * geometric_normal, direction};
}

// Whether `direction` meets the hit triangle's front face: glTF's counter-clockwise winding, the
// outside of a volume (shading and geometric normals are turned to the ray, so they cannot say).
inline bool meetsFrontFace(const RayScene& scene, const RayHit& hit, const vec3& direction) {
  const TriangleMesh& mesh = scene.mesh(hit.geometry);
  const uvec3& t = mesh.triangles[hit.primitive];
  const vec3 winding =
      glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
  return glm::dot(winding, direction) < 0.0f;
}

}  // namespace holo::reference
