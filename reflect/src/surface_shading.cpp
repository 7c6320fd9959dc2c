#include "holo/reflect/surface_shading.hpp"

#include <algorithm>
#include <cmath>

namespace holo::reflect {
namespace {

// The triangle of a hit and its barycentric weights.
struct Corner {
  uvec3 t;
  float w0, w1, w2;
};

Corner cornerOf(const TriangleMesh& mesh, const RayHit& hit) {
  const uvec3 t = mesh.triangles.at(hit.primitive);
  const float u = hit.barycentric.x, v = hit.barycentric.y;
  return {t, 1.0f - u - v, u, v};
}

template <class T>
T interpolate(const std::vector<T>& values, const Corner& c) {
  return c.w0 * values[c.t.x] + c.w1 * values[c.t.y] + c.w2 * values[c.t.z];
}

const std::vector<vec2>& uvSet(const TriangleMesh& mesh, int tex_coord) {
  return tex_coord == 1 ? mesh.uvs1 : mesh.uvs;
}

// uv units per metre on the triangle for a uv set: sqrt(uv area / world area); 0 when either is
// degenerate (the sharpest level is then used).
float uvPerMetre(const TriangleMesh& mesh, const Corner& c, const std::vector<vec2>& uvs) {
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
vec4 sampleSlot(const Model& model, const TriangleMesh& mesh, const Corner& c, const TextureRef& ref,
                float footprint_metres) {
  if (!ref.used() || std::size_t(ref.index) >= model.textures.size()) return vec4(1.0f);
  const std::vector<vec2>& uvs = uvSet(mesh, ref.tex_coord);
  const vec2 uv = ref.transform(uvs.empty() ? vec2(0.0f) : interpolate(uvs, c));
  const float scale = std::max(std::abs(ref.scale.x), std::abs(ref.scale.y));
  const float footprint = footprint_metres * uvPerMetre(mesh, c, uvs) * scale;
  return sampleTexture(model.textures[std::size_t(ref.index)], uv,
                       std::isfinite(footprint) ? footprint : 0.0f);
}

const Material& meshMaterial(const Model& model, std::size_t mesh) {
  static const Material kDefault{};
  const int m = model.meshes[mesh].material;
  return m >= 0 && std::size_t(m) < model.materials.size() ? model.materials[std::size_t(m)] : kDefault;
}

// The triangle's winding normal turned to agree with its vertex normals (a mirroring transform
// reverses the winding but not the normals); unnormalised, zero when degenerate.
vec3 outwardGeometricNormal(const TriangleMesh& mesh, const Corner& c) {
  const vec3 n = glm::cross(mesh.positions[c.t.y] - mesh.positions[c.t.x],
                            mesh.positions[c.t.z] - mesh.positions[c.t.x]);
  if (mesh.normals.empty()) return n;
  const vec3 vertex = mesh.normals[c.t.x] + mesh.normals[c.t.y] + mesh.normals[c.t.z];
  return glm::dot(n, vertex) < 0.0f ? -n : n;
}

float materialAlpha(const Model& model, const TriangleMesh& mesh, const Material& m, const Corner& c) {
  return m.alpha * sampleSlot(model, mesh, c, m.base_colour_texture, 0.0f).a;
}

// The normal-mapped normal around the (unflipped) interpolated normal n; n itself when the
// frame is degenerate.
vec3 mapNormal(const TriangleMesh& mesh, const Corner& c, const vec3& n, const vec4& texel, float scale) {
  vec3 t(0.0f);
  float handedness = 1.0f;
  if (!mesh.tangents.empty()) {
    const vec4 tangent = interpolate(mesh.tangents, c);
    t = vec3(tangent);
    handedness = mesh.tangents[c.t.x].w < 0.0f ? -1.0f : 1.0f;
  }
  t -= glm::dot(t, n) * n;
  const float len = glm::length(t);
  if (!(len > 1e-6f)) return n;
  t /= len;
  const vec3 b = handedness * glm::cross(n, t);
  const vec3 local = vec3(2.0f * texel.x - 1.0f, 2.0f * texel.y - 1.0f, 2.0f * texel.z - 1.0f);
  const vec3 mapped = local.x * scale * t + local.y * scale * b + local.z * n;
  const float mapped_len = glm::length(mapped);
  return mapped_len > 1e-6f && std::isfinite(mapped_len) ? mapped / mapped_len : n;
}

}  // namespace

bool needsOpacity(const Material& m) {
  return m.alpha_mode != AlphaMode::Opaque || (!m.double_sided && !m.transmissive());
}

float surfaceOpacity(const Model& model, std::size_t mesh_index, const Ray& ray, const RayHit& hit) {
  const TriangleMesh& mesh = model.meshes[mesh_index];
  const Material& m = meshMaterial(model, mesh_index);
  const Corner c = cornerOf(mesh, hit);
  if (!m.double_sided && !m.transmissive() && glm::dot(outwardGeometricNormal(mesh, c), ray.direction) > 0.0f)
    return 0.0f;
  switch (m.alpha_mode) {
    case AlphaMode::Opaque:
      return 1.0f;
    case AlphaMode::Mask:
      return materialAlpha(model, mesh, m, c) >= m.alpha_cutoff ? 1.0f : 0.0f;
    case AlphaMode::Blend:
      return std::clamp(materialAlpha(model, mesh, m, c), 0.0f, 1.0f);
  }
  return 1.0f;
}

SurfacePoint resolveSurface(const RenderScene& scene, const RayScene& traced, const Ray& ray,
                            const RayHit& hit, float cone_width) {
  SurfacePoint s;
  s.position = traced.position(ray, hit);
  s.geometric_normal = hit.geometric_normal;
  const Model& model = scene.relic();
  const std::size_t mesh_index = scene.relicMesh(hit, traced);
  const TriangleMesh& mesh = model.meshes[mesh_index];
  const Material& m = meshMaterial(model, mesh_index);
  const Corner c = cornerOf(mesh, hit);
  const float cosine = std::max(std::abs(glm::dot(hit.geometric_normal, ray.direction)), kMinFootprintCosine);
  const float footprint = std::isfinite(cone_width) ? std::max(cone_width, 0.0f) / cosine : 0.0f;

  const vec4 base = sampleSlot(model, mesh, c, m.base_colour_texture, footprint);
  s.material.base_colour = glm::clamp(m.base_colour * vec3(base), vec3(0.0f), vec3(1.0f));
  const vec4 orm = sampleSlot(model, mesh, c, m.metallic_roughness_texture, footprint);
  s.material.roughness = std::clamp(m.roughness * orm.g, 0.0f, 1.0f);
  s.material.metallic = std::clamp(m.metallic * orm.b, 0.0f, 1.0f);
  s.material.specular =
      std::clamp(m.specular * sampleSlot(model, mesh, c, m.specular_texture, footprint).a, 0.0f, 1.0f);
  // The specular colour may exceed 1 (dielectricF0 clamps the F0 it scales).
  s.material.specular_colour =
      m.specular_colour * vec3(sampleSlot(model, mesh, c, m.specular_colour_texture, footprint));
  // Glass, volume and clearcoat factors times their textures' channels (R transmission, G
  // thickness, R clearcoat, G clearcoat roughness): the path tracer's MaterialBsdf
  // (dielectric.hpp) reads them, the live refraction pass and coat the entry's.
  s.material.transmission = m.transmission * sampleSlot(model, mesh, c, m.transmission_texture, footprint).r;
  s.material.ior = m.ior;
  s.material.thin_walled =
      !(m.thickness * sampleSlot(model, mesh, c, m.thickness_texture, footprint).g > 0.0f);
  s.material.attenuation_colour = m.attenuation_colour;
  s.material.attenuation_distance = m.attenuation_distance;
  s.material.clearcoat = m.clearcoat * sampleSlot(model, mesh, c, m.clearcoat_texture, footprint).r;
  s.material.clearcoat_roughness =
      m.clearcoat_roughness * sampleSlot(model, mesh, c, m.clearcoat_roughness_texture, footprint).g;
  if (m.occlusion_texture.used()) {
    const float ao = sampleSlot(model, mesh, c, m.occlusion_texture, footprint).r;
    s.occlusion = std::clamp(1.0f + m.occlusion_strength * (ao - 1.0f), 0.0f, 1.0f);
  }
  if (m.emission != vec3(0.0f)) {
    const vec3 e = m.emission * vec3(sampleSlot(model, mesh, c, m.emissive_texture, footprint));
    s.emission = isFinite(e) ? glm::max(e, vec3(0.0f)) : vec3(0.0f);
  }
  if (const auto& material = scene.relicMaterialOverride()) s.material = *material;
  if (m.alpha_mode == AlphaMode::Blend) s.alpha = std::clamp(m.alpha * base.a, 0.0f, 1.0f);

  // The interpolated normal (the face's when the mesh has none or it degenerates), mapped, then
  // turned to the side the ray came from (double-sided: the back face's normal is reversed).
  vec3 interpolated = hit.geometric_normal;
  if (!mesh.normals.empty()) {
    const vec3 normal = interpolate(mesh.normals, c);
    const float len = glm::length(normal);
    if (len > 1e-12f && std::isfinite(len)) interpolated = normal / len;
  }
  // The normal of a map (or the interpolated one), turned to the side the ray came from.
  const vec3 wo = -ray.direction;
  const auto viewerSide = [&](const TextureRef& map, float map_scale) {
    vec3 n = interpolated;
    if (map.used()) n = mapNormal(mesh, c, n, sampleSlot(model, mesh, c, map, footprint), map_scale);
    if (glm::dot(n, ray.direction) > 0.0f) n = -n;
    // A mapped normal may face away from the viewer at grazing angles: bent just far enough
    // towards it that the shading sees the surface (the usual glTF viewer fix). Interpolated
    // normals without a map are left as they are (the images of unmapped relics do not change).
    const float nv = glm::dot(n, wo);
    constexpr float kMinFacing = 0.01f;
    if (map.used() && nv < kMinFacing) {
      const vec3 bent = n + (kMinFacing - nv) * wo;
      const float len = glm::length(bent);
      n = len > 1e-6f ? bent / len : wo;
    }
    return isFinite(n) ? n : hit.geometric_normal;
  };
  s.normal_mapped = m.normal_texture.used();
  s.normal = viewerSide(m.normal_texture, m.normal_scale);
  s.clearcoat_normal = m.clearcoat > 0.0f && m.clearcoat_normal_texture.used()
                           ? viewerSide(m.clearcoat_normal_texture, m.clearcoat_normal_scale)
                           : s.normal;
  return s;
}

SplitSumShading shadeSurface(const PrefilteredIbl& ibl, const SurfacePoint& surface, const vec3& wo) {
  SplitSumShading parts = ibl.shadeParts(surface.material, surface.normal, wo,
                                         glm::reflect(-wo, surface.normal), surface.position);
  parts.specular_scale *= surface.occlusion;
  parts.diffuse = surface.occlusion * parts.diffuse + surface.emission;
  return parts;
}

}  // namespace holo::reflect
