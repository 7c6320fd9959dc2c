#include "holo/sim/relics.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include "holo/core/error.hpp"
#include "holo/sim/shapes.hpp"

namespace holo::sim {

namespace {

Material metal(const std::string& name, const vec3& colour, float roughness) {
  Material m;
  m.name = name;
  m.base_colour = colour;
  m.metallic = 1.0f;
  m.roughness = roughness;
  m.double_sided = true;  // thin walls and open rims: both sides are seen
  return m;
}

// Glass-like thin walls: an outer profile going up, then an inner one coming back down, so the
// vessel has a rim and an inside that a reflection can see.
std::vector<vec2> withInnerWall(const std::vector<vec2>& outer, float thickness, float inner_bottom) {
  std::vector<vec2> profile = outer;
  for (auto it = outer.rbegin(); it != outer.rend(); ++it) {
    if (it->y < inner_bottom) break;
    profile.push_back({std::max(it->x - thickness, 0.0f), it->y});
  }
  profile.push_back({0.0f, inner_bottom});
  return profile;
}

Model vase() {
  Model model;
  model.materials.push_back(metal("bronze_polished", {0.95f, 0.64f, 0.54f}, 0.15f));
  const auto outer = smoothProfile({{0.0f, 0.0f},
                                    {0.055f, 0.0f},
                                    {0.05f, 0.015f},
                                    {0.04f, 0.03f},
                                    {0.085f, 0.08f},
                                    {0.11f, 0.13f},
                                    {0.09f, 0.19f},
                                    {0.045f, 0.235f},
                                    {0.04f, 0.255f},
                                    {0.06f, 0.28f}});
  TriangleMesh mesh = makeLathe(withInnerWall(outer, 0.006f, 0.2f), 64);
  mesh.name = "vase";
  model.meshes.push_back(std::move(mesh));
  return model;
}

Model kettle() {
  Model model;
  model.materials.push_back(metal("silver_brushed", {0.97f, 0.96f, 0.91f}, 0.35f));
  TriangleMesh all;
  all.name = "kettle";
  // Squat body with a shoulder and a lid.
  const auto body = smoothProfile({{0.0f, 0.0f},
                                   {0.07f, 0.0f},
                                   {0.1f, 0.02f},
                                   {0.115f, 0.07f},
                                   {0.1f, 0.13f},
                                   {0.06f, 0.165f},
                                   {0.05f, 0.17f},
                                   {0.05f, 0.18f},
                                   {0.0f, 0.19f}});
  appendMesh(all, makeLathe(body, 56));
  // Lid knob.
  appendMesh(all, makeSphere(0.022f, 8, 16), glm::translate(mat4(1.0f), vec3(0, 0.205f, 0)));
  // Spout: leaves the body low on +X, rises outwards and curves up to the tip.
  std::vector<vec3> spout;
  std::vector<float> spout_r;
  for (int i = 0; i <= 12; ++i) {
    const float t = static_cast<float>(i) / 12.0f;
    spout.push_back({0.085f + 0.09f * t, 0.05f + 0.14f * t * t + 0.05f * t, 0.0f});
    spout_r.push_back(0.022f - 0.012f * t);
  }
  appendMesh(all, makeTube(spout, spout_r, 16));
  // Handle: a half loop on -X, opposite the spout (the loop's hole makes the kettle non-convex).
  std::vector<vec3> handle;
  std::vector<float> handle_r;
  for (int i = 0; i <= 16; ++i) {
    const float a = kPi * static_cast<float>(i) / 16.0f;
    handle.push_back({-0.1f - 0.065f * std::sin(a), 0.1f + 0.05f * std::cos(a), 0.0f});
    handle_r.push_back(0.011f);
  }
  appendMesh(all, makeTube(handle, handle_r, 12));
  model.meshes.push_back(std::move(all));
  return model;
}

Model tripod() {
  Model model;
  model.materials.push_back(metal("bronze_patina", {0.8f, 0.5f, 0.3f}, 0.6f));
  TriangleMesh all;
  all.name = "tripod";
  // Bowl from y = 0.09 to the rim at 0.23.
  const auto outer =
      smoothProfile({{0.0f, 0.09f}, {0.06f, 0.095f}, {0.1f, 0.125f}, {0.115f, 0.18f}, {0.12f, 0.23f}});
  appendMesh(all, makeLathe(withInnerWall(outer, 0.008f, 0.105f), 56));
  // Three legs, splayed a little, from under the bowl to the ground.
  for (int k = 0; k < 3; ++k) {
    const float a = 2.0f * kPi * static_cast<float>(k) / 3.0f;
    const vec3 top{0.06f * std::sin(a), 0.11f, 0.06f * std::cos(a)};
    const vec3 foot{0.09f * std::sin(a), 0.0f, 0.09f * std::cos(a)};
    appendMesh(all, makeTube({top, 0.5f * (top + foot), foot}, {0.014f, 0.012f, 0.015f}, 12));
  }
  // Two upright loop handles on the rim (on +X and -X), like a ding's ears.
  for (int side : {-1, 1}) {
    std::vector<vec3> loop;
    std::vector<float> radii;
    for (int i = 0; i <= 14; ++i) {
      const float a = kPi * static_cast<float>(i) / 14.0f;
      loop.push_back({static_cast<float>(side) * 0.11f, 0.225f + 0.05f * std::sin(a), 0.035f * std::cos(a)});
      radii.push_back(0.008f);
    }
    appendMesh(all, makeTube(loop, radii, 10));
  }
  model.meshes.push_back(std::move(all));
  return model;
}

Model sphere() {
  Model model;
  model.materials.push_back(metal("mirror", {0.97f, 0.97f, 0.97f}, 0.0f));
  TriangleMesh mesh = makeSphere(0.14f, 48, 96);
  mesh.transform(glm::translate(mat4(1.0f), vec3(0, 0.14f, 0)));
  mesh.name = "sphere";
  model.meshes.push_back(std::move(mesh));
  return model;
}

}  // namespace

std::vector<std::string> relicNames() {
  return {"vase", "kettle", "tripod", "sphere"};
}

Model makeRelic(const std::string& name, const std::string& origin) {
  Model relic;
  if (name == "vase")
    relic = vase();
  else if (name == "kettle")
    relic = kettle();
  else if (name == "tripod")
    relic = tripod();
  else if (name == "sphere")
    relic = sphere();
  if (!relic.meshes.empty()) {
    fitOnPedestal(relic);  // exact size and placement, whatever the profiles above add up to
    return relic;
  }
  throw InputError(origin, "relic", "one of vase, kettle, tripod, sphere or a .gltf/.glb path", name);
}

void fitOnPedestal(Model& model) {
  const Bounds3 b = model.bounds();
  if (b.empty()) return;
  const vec3 e = b.extent();
  const float width = std::max(e.x, e.z);
  if (!(e.y > 1e-9f) || !std::isfinite(e.y) || !std::isfinite(width)) return;
  const float s = std::min(kRelicHeight / e.y, width > 0.0f ? kRelicMaxWidth / width : 1e30f);
  const vec3 c = b.center();
  mat4 T = glm::scale(mat4(1.0f), vec3(s));
  T = T * glm::translate(mat4(1.0f), vec3(-c.x, -b.lo.y, -c.z));
  model.transform(T);
}

}  // namespace holo::sim
