#include "holo/reflect/render_scene.hpp"

#include <algorithm>

#include "supporting_planes.hpp"
#include "surface_opacity.hpp"

namespace holo::reflect {

namespace {

const Material kDefaultMaterial{};

}  // namespace

RenderScene::RenderScene(const Model& relic, const std::vector<Model>& emitters)
    : relic_model_(relic),
      emitter_models_(emitters),
      all_(std::make_unique<RayScene>()),
      relic_(std::make_unique<RayScene>()) {
  for (std::size_t i = 0; i < relic_model_.meshes.size(); ++i) {
    auto& mesh = relic_model_.meshes[i];
    if (mesh.triangles.empty()) continue;
    const Material& material = materialOf({true, i, &relic_model_});
    // Either normal map (the base's or the clearcoat's) needs a tangent frame, as in the loader.
    const TextureRef& normal_map =
        material.normal_texture.used() ? material.normal_texture : material.clearcoat_normal_texture;
    if (normal_map.used() && mesh.tangents.size() != mesh.positions.size()) {
      if (mesh.normals.size() != mesh.positions.size()) mesh.computeNormals();
      mesh.computeTangents(normal_map.tex_coord);
    }
    const auto opacity = [this, i](const Ray& ray, const RayHit& hit) {
      // A transmissive override (a glass study on any mesh) culls no back face: a ray inside
      // the glass must be able to leave it.
      if (override_ && override_->transmission > 0.0f) return 1.0f;
      return surfaceOpacity(relic_model_, i, ray, hit);
    };
    const std::uint32_t id = all_->addMesh(mesh);
    surfaces_.resize(id + 1);
    surfaces_[id] = {true, i, &relic_model_};
    const std::uint32_t rid = relic_->addMesh(mesh);
    relic_mesh_.resize(rid + 1);
    relic_mesh_[rid] = i;
    if (needsOpacity(material)) {
      all_->setHitOpacity(id, opacity);
      relic_->setHitOpacity(rid, opacity);
    }
  }
  for (const Model& model : emitter_models_) {
    for (std::size_t i = 0; i < model.meshes.size(); ++i) {
      if (model.meshes[i].triangles.empty()) continue;
      const std::uint32_t id = all_->addMesh(model.meshes[i]);
      surfaces_.resize(id + 1);
      surfaces_[id] = {false, i, &model};
    }
  }
  all_->commit();
  relic_->commit();
  supporting_ = findSupportingPlanes(relic_model_).sides;
  // Degenerate triangles (a lathe's poles) bound nothing and lie in no plane: they do not count.
  for (std::size_t m = 0; m < supporting_.size() && relic_convex_; ++m) {
    const TriangleMesh& mesh = relic_model_.meshes[m];
    for (std::size_t t = 0; t < supporting_[m].size() && relic_convex_; ++t) {
      const uvec3& tri = mesh.triangles[t];
      const float area = glm::length(glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                                                mesh.positions[tri.z] - mesh.positions[tri.x]));
      relic_convex_ = supporting_[m][t] != 0 || !(area > 1e-12f);
    }
  }
}

bool RenderScene::mayMeetRelicAgain(const RayHit& hit, const vec3& direction) const {
  const std::size_t m = relic_mesh_.at(hit.geometry);
  // geometric_normal faces the side the hit was seen from; the winding's normal names the side.
  const TriangleMesh& mesh = relic_model_.meshes[m];
  const uvec3& tri = mesh.triangles[hit.primitive];
  const vec3 winding = glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                                  mesh.positions[tri.z] - mesh.positions[tri.x]);
  return mayMeetRelicAgain(m, hit.primitive, glm::dot(winding, hit.geometric_normal) > 0.0f, direction);
}

bool RenderScene::mayMeetRelicAgain(std::size_t mesh_index, std::uint32_t triangle, bool front,
                                    const vec3& direction) const {
  const std::uint8_t sides = supporting_.at(mesh_index).at(triangle);
  const std::uint8_t seen = front ? kFrontSupporting : kBackSupporting;
  if ((sides & seen) == 0) return true;
  const TriangleMesh& mesh = relic_model_.meshes[mesh_index];
  const uvec3& tri = mesh.triangles[triangle];
  const vec3 winding = glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                                  mesh.positions[tri.z] - mesh.positions[tri.x]);
  // Leaving to the supporting side: the whole relic is behind that plane.
  return !(glm::dot(direction, front ? winding : -winding) > 0.0f);
}

bool RenderScene::isRelic(std::uint32_t geometry) const {
  return geometry < surfaces_.size() && surfaces_[geometry].relic;
}

const Material& RenderScene::materialOf(const Surface& s) const {
  const int m = s.model->meshes[s.mesh].material;
  if (m < 0 || static_cast<std::size_t>(m) >= s.model->materials.size()) return kDefaultMaterial;
  return s.model->materials[static_cast<std::size_t>(m)];
}

vec3 RenderScene::emission(const RayHit& hit) const {
  if (!hit.hit() || hit.geometry >= surfaces_.size() || surfaces_[hit.geometry].relic) return vec3(0.0f);
  const vec3 e = materialOf(surfaces_[hit.geometry]).emission;
  return isFinite(e) ? glm::max(e, vec3(0.0f)) : vec3(0.0f);
}

std::size_t RenderScene::relicMesh(const RayHit& hit, const RayScene& scene) const {
  return &scene == relic_.get() ? relic_mesh_.at(hit.geometry) : surfaces_.at(hit.geometry).mesh;
}

const Material& RenderScene::relicGltfMaterial(const RayHit& hit, const RayScene& scene) const {
  const int m = relic_model_.meshes[relicMesh(hit, scene)].material;
  if (m < 0 || static_cast<std::size_t>(m) >= relic_model_.materials.size()) return kDefaultMaterial;
  return relic_model_.materials[static_cast<std::size_t>(m)];
}

}  // namespace holo::reflect
