#include "holo/reflect/render_scene.hpp"

#include <algorithm>

#include "holo/core/image.hpp"

namespace holo::reflect {

namespace {

const Material kDefaultMaterial{};

// Nearest texel with repeat wrapping (glTF's default sampler), as BGR(A) 8-bit -> [0,1] RGB.
vec3 texel(const cv::Mat& texture, const vec2& uv) {
  if (texture.empty()) return vec3(1.0f);
  const float fu = uv.x - std::floor(uv.x), fv = uv.y - std::floor(uv.y);
  const int x = std::clamp(static_cast<int>(fu * float(texture.cols)), 0, texture.cols - 1);
  const int y = std::clamp(static_cast<int>(fv * float(texture.rows)), 0, texture.rows - 1);
  const uchar* p = texture.ptr<uchar>(y) + x * texture.channels();
  return {p[2] / 255.0f, p[1] / 255.0f, p[0] / 255.0f};
}

}  // namespace

RenderScene::RenderScene(const Model& relic, const std::vector<Model>& emitters)
    : relic_model_(relic),
      emitter_models_(emitters),
      all_(std::make_unique<RayScene>()),
      relic_(std::make_unique<RayScene>()) {
  for (std::size_t i = 0; i < relic_model_.meshes.size(); ++i) {
    const auto& mesh = relic_model_.meshes[i];
    if (mesh.triangles.empty()) continue;
    const std::uint32_t id = all_->addMesh(mesh);
    surfaces_.resize(id + 1);
    surfaces_[id] = {true, i, &relic_model_};
    const std::uint32_t rid = relic_->addMesh(mesh);
    relic_mesh_.resize(rid + 1);
    relic_mesh_[rid] = i;
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

const Material& RenderScene::relicGltfMaterial(const RayHit& hit, const RayScene& scene) const {
  const std::size_t mesh =
      &scene == relic_.get() ? relic_mesh_.at(hit.geometry) : surfaces_.at(hit.geometry).mesh;
  const int mi = relic_model_.meshes[mesh].material;
  return (mi >= 0 && static_cast<std::size_t>(mi) < relic_model_.materials.size())
             ? relic_model_.materials[static_cast<std::size_t>(mi)]
             : kDefaultMaterial;
}

vec3 RenderScene::relicEmission(const RayHit& hit, const RayScene& scene) const {
  const vec3 e = relicGltfMaterial(hit, scene).emission;
  return isFinite(e) ? glm::max(e, vec3(0.0f)) : vec3(0.0f);
}

SurfaceMaterial RenderScene::relicMaterial(const RayHit& hit, const RayScene& scene) const {
  if (override_) return *override_;
  const Material& m = relicGltfMaterial(hit, scene);
  SurfaceMaterial s;
  s.base_colour = m.base_colour;
  s.metallic = m.metallic;
  s.roughness = m.roughness;
  s.specular = m.specular;
  s.specular_colour = m.specular_colour;
  s.transmission = m.transmission;
  s.ior = m.ior;
  s.thin_walled = !(m.thickness > 0.0f);
  s.attenuation_colour = m.attenuation_colour;
  s.attenuation_distance = m.attenuation_distance;
  s.clearcoat = m.clearcoat;
  s.clearcoat_roughness = m.clearcoat_roughness;
  const auto textureAt = [&](int index) -> const cv::Mat* {
    if (index < 0 || static_cast<std::size_t>(index) >= relic_model_.textures.size()) return nullptr;
    return &relic_model_.textures[static_cast<std::size_t>(index)].image();
  };
  if (const cv::Mat* t = textureAt(m.base_colour_texture.index)) {
    const vec3 c = texel(*t, scene.uv(hit));
    s.base_colour *= vec3(srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b));
  }
  if (const cv::Mat* t = textureAt(m.metallic_roughness_texture.index)) {
    const vec3 c = texel(*t, scene.uv(hit));
    s.roughness *= c.g;
    s.metallic *= c.b;
  }
  return s;
}

}  // namespace holo::reflect
