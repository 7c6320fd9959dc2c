#include "holo/ar/local_scene.hpp"

#include <algorithm>

#include "holo/core/error.hpp"
#include "holo/reflect/optics.hpp"

namespace holo::ar {
namespace {

reflect::SurfaceMaterial relicMaterial(const Material& m) {
  reflect::SurfaceMaterial s;
  s.base_colour = glm::clamp(m.base_colour, 0.0f, 1.0f);
  s.metallic = std::clamp(m.metallic, 0.0f, 1.0f);
  s.roughness = std::clamp(m.roughness, 0.0f, 1.0f);
  s.specular = std::clamp(m.specular, 0.0f, 1.0f);
  s.specular_colour = m.specular_colour;
  s.ior = m.ior;
  return s;
}

RelicGlass relicGlass(const Material& m) {
  RelicGlass g;
  g.transmission = std::clamp(m.transmission, 0.0f, 1.0f) * (1.0f - std::clamp(m.metallic, 0.0f, 1.0f));
  g.ior = std::max(m.ior, 1.0f);
  g.tint = glm::clamp(m.base_colour, 0.0f, 1.0f);
  g.thin_walled = !(m.thickness > 0.0f);
  if (!g.thin_walled) g.sigma = reflect::attenuationCoefficient(m.attenuation_colour, m.attenuation_distance);
  return g;
}

RelicBounds boundingSphere(const Model& relic) {
  Bounds3 box;
  for (const TriangleMesh& mesh : relic.meshes)
    for (const vec3& p : mesh.positions) box.extend(p);
  RelicBounds out;
  if (box.empty()) return out;
  out.centre = box.center();
  out.radius = 0.0f;
  for (const TriangleMesh& mesh : relic.meshes)
    for (const vec3& p : mesh.positions) out.radius = std::max(out.radius, glm::length(p - out.centre));
  out.radius = out.radius * (1.0f + 1e-4f) + 1e-5f;  // round-off: every vertex strictly inside
  return out;
}

}  // namespace

bool RelicBounds::mayHit(const Ray& ray) const {
  if (empty()) return false;
  const vec3 to_centre = centre - ray.origin;
  const float along = glm::dot(to_centre, ray.direction);
  const float distance2 = glm::dot(to_centre, to_centre);
  if (distance2 <= radius * radius) return true;  // the origin is inside
  if (along < 0.0f) return false;                 // the sphere is behind the ray
  return distance2 - along * along <= radius * radius;
}

RelicGeometry::RelicGeometry(const Model& relic)
    : rays_(std::make_unique<RayScene>()), bounds_(boundingSphere(relic)) {
  for (const TriangleMesh& mesh : relic.meshes) {
    TriangleMesh copy = mesh;
    if (copy.normals.size() != copy.positions.size()) copy.computeNormals();
    rays_->addMesh(copy);
    const auto index = static_cast<std::size_t>(mesh.material);
    materials_.push_back(index < relic.materials.size() ? relicMaterial(relic.materials[index])
                                                        : reflect::SurfaceMaterial{});
    glass_.push_back(index < relic.materials.size() ? relicGlass(relic.materials[index]) : RelicGlass{});
  }
  rays_->commit();
}

bool RelicGeometry::transmits() const {
  return std::any_of(glass_.begin(), glass_.end(), [](const RelicGlass& g) { return g.transmission > 0.0f; });
}

LocalScene::LocalScene(RealSurface real, const Model& relic, const reflect::Environment& environment)
    : LocalScene(std::move(real), std::make_shared<const RelicGeometry>(relic), environment) {}

LocalScene::LocalScene(RealSurface real, std::shared_ptr<const RelicGeometry> relic,
                       const reflect::Environment& environment)
    : real_surface_(std::move(real)),
      relic_(std::move(relic)),
      real_(std::make_unique<RayScene>()),
      environment_(environment) {
  if (real_surface_.albedo.size() != real_surface_.mesh.positions.size())
    throw InputError("AR local scene", "real surface albedo",
                     "one albedo per vertex of the real surface's mesh");
  if (real_surface_.mesh.normals.size() != real_surface_.mesh.positions.size())
    real_surface_.mesh.computeNormals();
  real_->addMesh(real_surface_.mesh);
  real_->commit();
}

RayHit LocalScene::intersect(SceneContent content, const Ray& ray) const {
  const RayHit real = real_->intersect(ray);
  // The relic only nearer than the real hit, and only for a ray that can meet its sphere.
  if (content == SceneContent::kMixed && relic_->bounds().mayHit(ray)) {
    RayHit relic = relic_->rays().intersect(ray, 0.0f, real.hit() ? real.t : 1e30f);
    if (relic.hit()) {
      relic.geometry += 1;
      return relic;
    }
  }
  return real;
}

bool LocalScene::occluded(SceneContent content, const Ray& ray) const {
  return real_->occluded(ray) ||
         (content == SceneContent::kMixed && relic_->bounds().mayHit(ray) && relic_->rays().occluded(ray));
}

vec3 LocalScene::shadingNormal(const RayHit& hit, const vec3& ray_direction) const {
  if (!isRelic(hit.geometry)) return real_->shadingNormal(hit, ray_direction);
  RayHit on_relic = hit;
  on_relic.geometry -= 1;
  return relic_->rays().shadingNormal(on_relic, ray_direction);
}

reflect::Bsdf LocalScene::bsdfAt(const Ray& ray, const RayHit& hit) const {
  const vec3 normal = shadingNormal(hit, ray.direction);
  if (isRelic(hit.geometry)) return reflect::Bsdf(relic_->material(hit.geometry - 1), normal);
  reflect::SurfaceMaterial lambert;
  lambert.base_colour = realAlbedo(hit);
  lambert.specular = 0.0f;  // a pure Lambert surface (bsdf.hpp)
  lambert.roughness = 1.0f;
  return reflect::Bsdf(lambert, normal);
}

vec3 LocalScene::realAlbedo(const RayHit& hit) const {
  const uvec3 tri = real_surface_.mesh.triangles[hit.primitive];
  const float u = hit.barycentric.x, v = hit.barycentric.y;
  return (1.0f - u - v) * real_surface_.albedo[tri.x] + u * real_surface_.albedo[tri.y] +
         v * real_surface_.albedo[tri.z];
}

void LocalScene::setRealAlbedo(std::vector<vec3> albedo) {
  if (albedo.size() != real_surface_.mesh.positions.size())
    throw InputError("AR local scene", "real surface albedo",
                     "one albedo per vertex of the real surface's mesh");
  real_surface_.albedo = std::move(albedo);
}

const RelicGlass* LocalScene::glassAt(const RayHit& hit) const {
  if (!isRelic(hit.geometry)) return nullptr;
  const RelicGlass& glass = relic_->glass(hit.geometry - 1);
  return glass.transmission > 0.0f ? &glass : nullptr;
}

const TriangleMesh& LocalScene::meshOf(const RayHit& hit) const {
  return isRelic(hit.geometry) ? relic_->rays().mesh(hit.geometry - 1) : real_->mesh(kRealGeometry);
}

bool LocalScene::frontFace(const Ray& ray, const RayHit& hit) const {
  const TriangleMesh& mesh = meshOf(hit);
  const uvec3 tri = mesh.triangles[hit.primitive];
  const vec3 winding = glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                                  mesh.positions[tri.z] - mesh.positions[tri.x]);
  return glm::dot(winding, ray.direction) < 0.0f;
}

vec3 LocalScene::offsetOrigin(const Ray& ray, const RayHit& hit, const vec3& towards) const {
  const vec3 p = ray.origin + hit.t * ray.direction;
  const vec3 n = hit.geometric_normal;  // faces the incoming ray
  const float side = glm::dot(n, towards) >= 0.0f ? 1.0f : -1.0f;
  const float scale = 1e-4f * (1.0f + glm::length(p));
  return p + side * scale * n;
}

}  // namespace holo::ar
