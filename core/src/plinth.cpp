#include "holo/core/plinth.hpp"

#include <cmath>
#include <string>

#include "holo/core/shapes.hpp"

namespace holo {

PlinthSettings parsePlinth(const ConfigNode& node) {
  if (!node.isMap()) node.fail("a map with half_width, height, gap and albedo");
  node.rejectUnknownKeys({"half_width", "height", "gap", "albedo"});
  PlinthSettings s;
  s.half_width = node.getInRange("half_width", s.half_width, 0.01f, 2.0f);
  s.height = node.getInRange("height", s.height, 0.005f, 3.0f);
  s.gap = node.getInRange("gap", s.gap, 0.0f, 1.0f);
  if (node.has("albedo")) {
    const ConfigNode albedo = node["albedo"];
    const char* expected = "an albedo: one number or three (RGB), each in [0, 1]";
    if (albedo.isSequence()) {
      if (albedo.size() != 3) albedo.fail(expected, std::to_string(albedo.size()) + " numbers");
      s.albedo = albedo.as<vec3>();
    } else {
      s.albedo = vec3(albedo.as<float>());
    }
    for (int c = 0; c < 3; ++c)
      if (!(s.albedo[c] >= 0.0f && s.albedo[c] <= 1.0f)) albedo.fail(expected, std::to_string(s.albedo[c]));
  }
  return s;
}

PlinthBox placePlinth(const PlinthSettings& settings, const Bounds3& relic_bounds) {
  PlinthBox box;
  const vec3 c = relic_bounds.empty() ? vec3(0.0f) : relic_bounds.center();
  box.centre = vec2(c.x, c.z);
  box.half_width = settings.half_width;
  box.top = (relic_bounds.empty() ? 0.0f : relic_bounds.lo.y) - settings.gap;
  box.bottom = box.top - settings.height;
  box.albedo = settings.albedo;
  return box;
}

std::optional<PlinthHit> intersectPlinth(const PlinthBox& box, const Ray& ray) {
  const Bounds3 b = box.bounds();
  float t_near = -1e30f, t_far = 1e30f;
  int axis_near = -1;
  float sign_near = 1.0f;
  for (int a = 0; a < 3; ++a) {
    const float d = ray.direction[a], o = ray.origin[a];
    if (d == 0.0f) {
      if (o < b.lo[a] || o > b.hi[a]) return std::nullopt;
      continue;
    }
    float t0 = (b.lo[a] - o) / d, t1 = (b.hi[a] - o) / d;
    float sign = -1.0f;  // entering through the low face: its normal points to -axis
    if (t0 > t1) {
      std::swap(t0, t1);
      sign = 1.0f;
    }
    if (t0 > t_near) {
      t_near = t0;
      axis_near = a;
      sign_near = sign;
    }
    t_far = std::min(t_far, t1);
  }
  if (axis_near < 0 || t_near > t_far || t_near <= 0.0f) return std::nullopt;
  PlinthHit hit;
  hit.t = t_near;
  hit.normal = vec3(0.0f);
  hit.normal[axis_near] = sign_near;
  return hit;
}

void appendPlinth(Model& model, const PlinthBox& box) {
  TriangleMesh mesh = makeBox(vec3(box.half_width, 0.5f * (box.top - box.bottom), box.half_width));
  const vec3 offset(box.centre.x, 0.5f * (box.top + box.bottom), box.centre.y);
  for (vec3& p : mesh.positions) p += offset;
  Material m;
  m.name = "plinth";
  m.base_colour = box.albedo;
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.specular = 0.0f;
  mesh.material = int(model.materials.size());
  model.materials.push_back(m);
  model.meshes.push_back(std::move(mesh));
}

}  // namespace holo
