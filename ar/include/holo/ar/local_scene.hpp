// The local scene of an AR composite (Debevec's split): the real surfaces near the relic, each a
// Lambertian reflector with an albedo per vertex, and the virtual relic with its glTF materials
// (reflect::Bsdf: metallic-roughness GGX and Lambert; textures and clearcoat are not read), lit by
// the panorama at infinity. Everything farther than the local scene is the panorama. No surface of
// it emits.
//
// A transmissive relic material (KHR_materials_transmission) is smooth glass (RelicGlass): with
// probability `transmission` a scattering there is the dielectric interface (exact Fresnel
// reflection or Snell refraction, total internal reflection included), else the opaque lobes
// above; a material with thickness > 0 (KHR_materials_volume) is a closed solid absorbing by
// Beer-Lambert inside, one of thickness 0 thin-walled (light passes straight through). Its
// roughness is not read (the interface is smooth).
//
// Two ray scenes over the same surfaces: mixed (real + relic) and real only, so the radiance of
// either (what differential rendering differences) can be traced.
// Units: metres in the world (pyramid) frame; albedo linear RGB in [0, 1].
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "holo/core/mesh.hpp"
#include "holo/core/ray_scene.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/environment.hpp"

namespace holo::ar {

// Real surfaces: one mesh (world frame, normals per vertex) and its albedo per vertex.
struct RealSurface {
  TriangleMesh mesh;
  std::vector<vec3> albedo;  // same size as mesh.positions
};

enum class SceneContent { kReal, kMixed };

// A sphere holding every vertex of the relic (world frame, metres); radius < 0: no relic.
struct RelicBounds {
  vec3 centre{0.0f};
  float radius = -1.0f;

  bool empty() const { return radius < 0.0f; }
  // Whether the ray (unit direction) from its origin can meet the sphere: false only where it
  // certainly misses the relic.
  bool mayHit(const Ray& ray) const;
};

// The dielectric part of a transmissive relic material.
struct RelicGlass {
  float transmission = 0.0f;  // [0, 1]: the share of scatterings that are the interface's
  float ior = 1.5f;           // >= 1
  vec3 tint{1.0f};            // base colour: multiplies light entering (or crossing a thin wall)
  vec3 sigma{0.0f};           // Beer-Lambert coefficient inside, 1/m (reflect::attenuationCoefficient)
  bool thin_walled = false;   // thickness 0: no bending, no volume
};

// The relic's part of a local scene: its meshes' ray scene (the relic alone), materials, glass and
// bounding sphere. Built once per relic and shared by the local scenes of successive frames, so a
// new depth surface rebuilds only the real surface's ray scene.
class RelicGeometry {
 public:
  explicit RelicGeometry(const Model& relic);
  RelicGeometry(const RelicGeometry&) = delete;
  RelicGeometry& operator=(const RelicGeometry&) = delete;

  const RayScene& rays() const { return *rays_; }  // geometry id: the relic mesh's index
  const RelicBounds& bounds() const { return bounds_; }
  const reflect::SurfaceMaterial& material(std::uint32_t mesh) const { return materials_[mesh]; }
  const RelicGlass& glass(std::uint32_t mesh) const { return glass_[mesh]; }
  bool transmits() const;  // whether any of its materials is glass

 private:
  std::unique_ptr<RayScene> rays_;
  std::vector<reflect::SurfaceMaterial> materials_;  // per relic mesh
  std::vector<RelicGlass> glass_;                    // per relic mesh; transmission 0: opaque
  RelicBounds bounds_;
};

class LocalScene {
 public:
  // The environment must outlive the scene. Throws InputError when the albedo does not match the
  // mesh's vertices.
  LocalScene(RealSurface real, const Model& relic, const reflect::Environment& environment);
  LocalScene(RealSurface real, std::shared_ptr<const RelicGeometry> relic,
             const reflect::Environment& environment);
  LocalScene(const LocalScene&) = delete;
  LocalScene& operator=(const LocalScene&) = delete;

  // The nearest hit of the scene `content` (kReal: the real surface alone; kMixed: and the relic,
  // whose meshes have geometry ids 1, 2, ...; the real surface's is kRealGeometry), and whether
  // anything of it is hit.
  RayHit intersect(SceneContent content, const Ray& ray) const;
  bool occluded(SceneContent content, const Ray& ray) const;
  // The shading normal at a hit, facing against `ray_direction`.
  vec3 shadingNormal(const RayHit& hit, const vec3& ray_direction) const;
  bool isRelic(std::uint32_t geometry) const { return geometry != kRealGeometry; }
  const reflect::Environment& environment() const { return environment_; }
  // The BSDF at a hit seen along `ray` (its direction unit, towards the surface).
  reflect::Bsdf bsdfAt(const Ray& ray, const RayHit& hit) const;
  // The glass of a relic hit; nullptr for an opaque material.
  const RelicGlass* glassAt(const RayHit& hit) const;
  // Whether a ray meets the hit surface from its glTF front (the winding's side: outside a solid).
  bool frontFace(const Ray& ray, const RayHit& hit) const;
  // An origin for rays leaving the hit: nudged off the surface to the side of `towards`.
  vec3 offsetOrigin(const Ray& ray, const RayHit& hit, const vec3& towards) const;
  const RealSurface& real() const { return real_surface_; }
  const RelicBounds& relicBounds() const { return relic_->bounds(); }
  bool relicTransmits() const { return relic_->transmits(); }
  // The albedo of the real surface at a hit on it.
  vec3 realAlbedo(const RayHit& hit) const;
  // New albedo for the real surface's vertices (its geometry and ray scenes kept). Throws
  // InputError when the count does not match the vertices'.
  void setRealAlbedo(std::vector<vec3> albedo);

  static constexpr std::uint32_t kRealGeometry = 0;

 private:
  const TriangleMesh& meshOf(const RayHit& hit) const;

  RealSurface real_surface_;
  std::shared_ptr<const RelicGeometry> relic_;
  std::unique_ptr<RayScene> real_;
  const reflect::Environment& environment_;
};

}  // namespace holo::ar
