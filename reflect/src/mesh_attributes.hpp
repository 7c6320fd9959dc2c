// What a ray hit on a relic mesh carries: the triangle and its barycentric weights, vertex data
// interpolated there, the material of the mesh and its texture slots filtered at the hit. Shared
// by the surface shading and the opacity the ray queries see, so both read a hit alike.
#pragma once

#include <cmath>
#include <vector>

#include "holo/core/mesh.hpp"
#include "holo/core/ray_scene.hpp"
#include "holo/core/texture.hpp"

namespace holo::reflect {

// The triangle of a hit and its barycentric weights.
struct Corner {
  uvec3 t;
  float w0, w1, w2;
};

inline Corner cornerOf(const TriangleMesh& mesh, const RayHit& hit) {
  const uvec3 t = mesh.triangles.at(hit.primitive);
  const float u = hit.barycentric.x, v = hit.barycentric.y;
  return {t, 1.0f - u - v, u, v};
}

template <class T>
T interpolate(const std::vector<T>& values, const Corner& c) {
  return c.w0 * values[c.t.x] + c.w1 * values[c.t.y] + c.w2 * values[c.t.z];
}

inline const std::vector<vec2>& uvSet(const TriangleMesh& mesh, int tex_coord) {
  return tex_coord == 1 ? mesh.uvs1 : mesh.uvs;
}

// uv units per metre on the triangle for a uv set: sqrt(uv area / world area); 0 when either is
// degenerate (the sharpest level is then used).
inline float uvPerMetre(const TriangleMesh& mesh, const Corner& c, const std::vector<vec2>& uvs) {
  if (uvs.empty()) return 0.0f;
  const vec3 e1 = mesh.positions[c.t.y] - mesh.positions[c.t.x];
  const vec3 e2 = mesh.positions[c.t.z] - mesh.positions[c.t.x];
  const float world = glm::length(glm::cross(e1, e2));
  const vec2 d1 = uvs[c.t.y] - uvs[c.t.x], d2 = uvs[c.t.z] - uvs[c.t.x];
  const float uv = std::abs(d1.x * d2.y - d1.y * d2.x);
  const float ratio = uv / world;
  return world > 0.0f && std::isfinite(ratio) ? std::sqrt(ratio) : 0.0f;
}

// A texture slot's filtered value at the hit; (1,1,1,1) when the slot is unused.
inline vec4 sampleSlot(const Model& model, const TriangleMesh& mesh, const Corner& c, const TextureRef& ref,
                       float footprint_metres) {
  if (!ref.used() || std::size_t(ref.index) >= model.textures.size()) return vec4(1.0f);
  const std::vector<vec2>& uvs = uvSet(mesh, ref.tex_coord);
  const vec2 uv = ref.transform(uvs.empty() ? vec2(0.0f) : interpolate(uvs, c));
  const float scale = std::max(std::abs(ref.scale.x), std::abs(ref.scale.y));
  const float footprint = footprint_metres * uvPerMetre(mesh, c, uvs) * scale;
  return sampleTexture(model.textures[std::size_t(ref.index)], uv,
                       std::isfinite(footprint) ? footprint : 0.0f);
}

inline const Material& meshMaterial(const Model& model, std::size_t mesh) {
  static const Material kDefault{};
  const int m = model.meshes[mesh].material;
  return m >= 0 && std::size_t(m) < model.materials.size() ? model.materials[std::size_t(m)] : kDefault;
}

// The triangle's winding normal turned to agree with its vertex normals (a mirroring transform
// reverses the winding but not the normals); unnormalised, zero when degenerate.
inline vec3 outwardGeometricNormal(const TriangleMesh& mesh, const Corner& c) {
  const vec3 n = glm::cross(mesh.positions[c.t.y] - mesh.positions[c.t.x],
                            mesh.positions[c.t.z] - mesh.positions[c.t.x]);
  if (mesh.normals.empty()) return n;
  const vec3 vertex = mesh.normals[c.t.x] + mesh.normals[c.t.y] + mesh.normals[c.t.z];
  return glm::dot(n, vertex) < 0.0f ? -n : n;
}

inline float materialAlpha(const Model& model, const TriangleMesh& mesh, const Material& m, const Corner& c) {
  return m.alpha * sampleSlot(model, mesh, c, m.base_colour_texture, 0.0f).a;
}

}  // namespace holo::reflect
