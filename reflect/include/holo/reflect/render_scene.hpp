// What the renderers trace: the relic (the only surface with a BRDF) and the emitters (the hall,
// visitors and what they carry: diffuse emitters whose radiance is their Material::emission, the
// light model of sim/museum.hpp), in one Embree scene, plus a relic-only scene for primary rays
// (the pyramid's monitors show the relic alone; everything real is seen only in reflections).
// Models are copied in; a relic mesh whose material has a normal map but no tangents gets them
// (TriangleMesh::computeTangents), and relic meshes whose material culls back faces or has an
// alpha mode answer the ray queries' opacity (surface_shading.hpp), so both scenes pass through
// cut-out texels. Positions in metres, world frame.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "holo/core/ray_scene.hpp"
#include "holo/reflect/bsdf.hpp"

namespace holo::reflect {

class RenderScene {
 public:
  // `relic` may be empty (nothing to see); `emitters` may be empty (the relic under the sky).
  RenderScene(const Model& relic, const std::vector<Model>& emitters);
  RenderScene(const RenderScene&) = delete;  // surfaces point into the owned models
  RenderScene& operator=(const RenderScene&) = delete;

  const RayScene& all() const { return *all_; }          // relic + emitters
  const RayScene& relicOnly() const { return *relic_; }  // primary visibility

  bool isRelic(std::uint32_t geometry) const;  // geometry id of all()
  // Emitted radiance (RGB) of an emitter hit in all(); 0 for the relic.
  vec3 emission(const RayHit& hit) const;
  // The relic mesh (index into relic().meshes) a hit of either scene is on.
  std::size_t relicMesh(const RayHit& hit, const RayScene& scene) const;
  // The relic's glTF material at a hit of either scene (a default one for a mesh without any);
  // lives as long as the scene.
  const Material& relicGltfMaterial(const RayHit& hit, const RayScene& scene) const;
  // Every relic surface gets this material's parameters instead of its glTF ones (base colour,
  // metallic, roughness and specular textures ignored; normal, occlusion and emission maps and
  // the opacity stay the glTF material's, except that a transmissive override culls no back
  // face): for analytic tests and material studies that glTF cannot state (a pure Lambert surface
  // needs SurfaceMaterial::specular = 0).
  void overrideRelicMaterial(const SurfaceMaterial& material) { override_ = material; }
  const std::optional<SurfaceMaterial>& relicMaterialOverride() const { return override_; }
  const Model& relic() const { return relic_model_; }
  Bounds3 relicBounds() const { return relic_model_.bounds(); }
  // Whether a ray leaving the relic at `hit` (a relic hit of relicOnly()) in `direction` may meet
  // the relic again. False only where it cannot: the hit's triangle lies in a supporting plane of
  // the relic (the whole relic behind it, up to 1e-5 of its size) on the side the hit was seen
  // from, and `direction` leaves to that side. The interreflection casts no mirror ray there, so
  // a convex relic casts none. Decided at construction from the relic's convex hull (Qhull).
  bool mayMeetRelicAgain(const RayHit& hit, const vec3& direction) const;
  // The same decision at triangle `triangle` of relic mesh `mesh`, seen from the side its
  // winding's normal points to (`front`) or the other: any direction, e.g. a rough lobe's.
  bool mayMeetRelicAgain(std::size_t mesh, std::uint32_t triangle, bool front, const vec3& direction) const;
  // Every relic triangle lies in a supporting plane of the relic (the same decision): no point of
  // a convex relic sees another, so it casts no shadow on itself.
  bool relicIsConvex() const { return relic_convex_; }

 private:
  struct Surface {
    bool relic = false;
    std::size_t mesh = 0;  // index into its model's meshes
    const Model* model = nullptr;
  };
  const Material& materialOf(const Surface& s) const;
  Model relic_model_;
  std::vector<Model> emitter_models_;
  std::vector<Surface> surfaces_;        // by geometry id of all()
  std::vector<std::size_t> relic_mesh_;  // geometry id of relicOnly() -> relic mesh
  std::unique_ptr<RayScene> all_;
  std::unique_ptr<RayScene> relic_;
  std::optional<SurfaceMaterial> override_;
  std::vector<std::vector<std::uint8_t>> supporting_;  // by relic mesh, triangle: supporting_planes.hpp
  bool relic_convex_ = true;
};

}  // namespace holo::reflect
