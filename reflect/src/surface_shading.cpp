#include "holo/reflect/surface_shading.hpp"

#include <algorithm>
#include <cmath>

#include "mesh_attributes.hpp"

namespace holo::reflect {
namespace {

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
  s.location.mesh = std::uint32_t(mesh_index);
  s.location.triangle = hit.primitive;
  s.location.barycentric = hit.barycentric;
  const vec3 winding = glm::cross(mesh.positions[c.t.y] - mesh.positions[c.t.x],
                                  mesh.positions[c.t.z] - mesh.positions[c.t.x]);
  s.location.front = !(glm::dot(winding, hit.geometric_normal) < 0.0f);
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
