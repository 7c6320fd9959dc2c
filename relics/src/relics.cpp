#include "holo/relics/relics.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include "holo/core/error.hpp"
#include "holo/core/shapes.hpp"

namespace holo::relics {

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

Material glass(const std::string& name, const vec3& tint, float tint_distance, float ior, float wall) {
  Material m;
  m.name = name;
  m.base_colour = vec3(1.0f);
  m.metallic = 0.0f;
  m.roughness = 0.0f;
  m.transmission = 1.0f;
  m.ior = ior;
  m.thickness = wall;  // KHR_materials_volume: a closed solid, refracting on entry and exit
  m.attenuation_colour = tint;
  m.attenuation_distance = tint_distance;
  return m;
}

// Thick-walled tinted glass: the wall (outer surface up, rim, inner surface down, a thick base)
// is one closed solid, so a ray through the vase refracts four times and is tinted by its path
// length in the glass (Beer-Lambert); built at its final size, so the attenuation distance is in
// metres of the fitted relic.
Model glassVase() {
  Model model;
  constexpr float kWall = 0.012f;
  model.materials.push_back(glass("glass_tinted", {0.45f, 0.78f, 0.70f}, 0.04f, 1.5f, kWall));
  // Each smooth stretch is its own lathe, so the creases (base edge, rim, inner floor) keep
  // their sharp normals: a normal smoothed across a crease would refract rays back out.
  constexpr float kInnerFloor = 0.025f;
  const auto outer = smoothProfile({{0.06f, 0.0f},
                                    {0.065f, 0.01f},
                                    {0.09f, 0.06f},
                                    {0.105f, 0.12f},
                                    {0.085f, 0.19f},
                                    {0.055f, 0.24f},
                                    {0.05f, 0.26f},
                                    {0.062f, 0.28f}});
  std::vector<vec2> inner;
  for (auto it = outer.rbegin(); it != outer.rend() && it->y >= kInnerFloor; ++it)
    inner.push_back({it->x - kWall, it->y});
  TriangleMesh mesh;
  for (const auto& part :
       {std::vector<vec2>{{0.0f, 0.0f}, outer.front()}, outer, std::vector<vec2>{outer.back(), inner.front()},
        inner, std::vector<vec2>{inner.back(), {0.0f, kInnerFloor}}})
    appendMesh(mesh, makeLathe(part, 96));
  mesh.name = "glass_vase";
  model.meshes.push_back(std::move(mesh));
  return model;
}

// Round brilliant-like gem, table up: a 16-sided girdle band, a crown of two facet rings up to a
// 16-sided table, and a pavilion of two facet rings down to the culet. Flat-shaded (every facet its
// own vertices) with IOR 2.42 (diamond): most rays entering the table leave only after several
// total internal reflections on the pavilion.
Model crystal() {
  Model model;
  Material m = glass("diamond", {0.92f, 0.95f, 1.0f}, 0.5f, 2.42f, 0.1f);
  model.materials.push_back(m);
  constexpr int kGirdle = 16;
  constexpr float kR = 0.14f;            // girdle radius, metres
  constexpr float kTableR = 0.53f * kR;  // table radius
  constexpr float kCrown = 0.16f * 2.0f * kR, kPavilion = 0.43f * 2.0f * kR, kGirdleH = 0.01f;
  const float y0 = kPavilion;                         // girdle bottom above the culet, which stands at y = 0
  const vec3 centre(0.0f, y0 + 0.3f * kCrown, 0.0f);  // inside the convex gem: orients the facets
  TriangleMesh mesh;
  mesh.name = "crystal";
  auto ring = [](int k, int n, float r, float y, float phase) {
    const float a = 2.0f * kPi * (static_cast<float>(k) + phase) / static_cast<float>(n);
    return vec3(r * std::cos(a), y, r * std::sin(a));
  };
  auto facet = [&](vec3 a, vec3 b, vec3 c) {
    vec3 n = glm::cross(b - a, c - a);
    if (glm::dot(n, (a + b + c) / 3.0f - centre) < 0.0f) {
      std::swap(b, c);  // counter-clockwise seen from outside: glTF's front face
      n = -n;
    }
    n = glm::normalize(n);
    const auto i = static_cast<std::uint32_t>(mesh.positions.size());
    for (const vec3& p : {a, b, c}) {
      mesh.positions.push_back(p);
      mesh.normals.push_back(n);
    }
    mesh.triangles.push_back({i, i + 1, i + 2});
  };
  const vec3 culet(0.0f, 0.0f, 0.0f);
  const vec3 table_centre(0.0f, y0 + kGirdleH + kCrown, 0.0f);
  for (int k = 0; k < kGirdle; ++k) {
    const vec3 g0 = ring(k, kGirdle, kR, y0, 0.0f), g1 = ring(k + 1, kGirdle, kR, y0, 0.0f);
    const vec3 u0 = ring(k, kGirdle, kR, y0 + kGirdleH, 0.0f),
               u1 = ring(k + 1, kGirdle, kR, y0 + kGirdleH, 0.0f);
    // Pavilion: a main facet from the girdle edge to a point half way down, then to the culet.
    const vec3 mid = ring(k, kGirdle, 0.45f * kR, 0.45f * y0, 0.5f);
    const vec3 mid_next = ring(k + 1, kGirdle, 0.45f * kR, 0.45f * y0, 0.5f);
    facet(g0, g1, mid);
    facet(g1, mid_next, mid);
    facet(mid, mid_next, culet);
    // Girdle band.
    facet(g0, g1, u1);
    facet(g0, u1, u0);
    // Crown: a band of quads (two facets each) to a bezel ring, then alternating star facets
    // up to the table's ring, set half a step round.
    const vec3 b0 = ring(k, kGirdle, 0.8f * kR, y0 + kGirdleH + 0.45f * kCrown, 0.0f);
    const vec3 b1 = ring(k + 1, kGirdle, 0.8f * kR, y0 + kGirdleH + 0.45f * kCrown, 0.0f);
    const vec3 t = ring(k, kGirdle, kTableR, table_centre.y, 0.5f);
    const vec3 t_next = ring(k + 1, kGirdle, kTableR, table_centre.y, 0.5f);
    facet(u0, u1, b1);
    facet(u0, b1, b0);
    facet(b0, b1, t);
    facet(b1, t_next, t);
    // Table.
    facet(table_centre, t, t_next);
  }
  model.meshes.push_back(std::move(mesh));
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

// A thick open bowl, one closed solid: the outer wall up from a foot ring, round over the rim,
// the inner wall down to a floor 2.8 cm above the base. Its inside sees itself over most of its
// hemisphere: the relic that self-occlusion and the rough interreflection are measured on.
Model bowl(Material material) {
  Model model;
  model.materials.push_back(std::move(material));
  TriangleMesh mesh = makeLathe(smoothProfile({{0.0f, 0.0f},
                                               {0.05f, 0.0f},
                                               {0.056f, 0.01f},
                                               {0.09f, 0.03f},
                                               {0.125f, 0.07f},
                                               {0.145f, 0.11f},
                                               {0.15f, 0.128f},
                                               {0.143f, 0.136f},
                                               {0.135f, 0.126f},
                                               {0.127f, 0.1f},
                                               {0.105f, 0.062f},
                                               {0.07f, 0.037f},
                                               {0.0f, 0.028f}}),
                                64);
  mesh.name = "bowl";
  model.meshes.push_back(std::move(mesh));
  return model;
}

// Matte glazed clay: a Lambert surface (KHR_materials_specular's specular = 0: no reflection lobe).
Material lambert(const std::string& name, const vec3& colour) {
  Material m;
  m.name = name;
  m.base_colour = colour;
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.specular = 0.0f;
  return m;
}

}  // namespace

std::vector<std::string> relicNames() {
  return {"vase", "kettle", "tripod", "sphere", "glass-vase", "crystal", "bowl", "metal-bowl"};
}

std::string relicNameList() {
  std::string list;
  for (const auto& name : relicNames()) list += (list.empty() ? "" : ", ") + name;
  return list;
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
  else if (name == "glass-vase")
    relic = glassVase();
  else if (name == "crystal")
    relic = crystal();
  else if (name == "bowl")
    relic = bowl(lambert("clay_matte", {0.8f, 0.74f, 0.64f}));
  else if (name == "metal-bowl") {
    Material m = metal("silver_satin", {0.96f, 0.93f, 0.88f}, 0.4f);
    m.double_sided = false;  // a closed solid: only its outside is ever seen
    relic = bowl(m);
  }
  if (!relic.meshes.empty()) {
    fitOnPedestal(relic);  // exact size and placement, whatever the profiles above add up to
    return relic;
  }
  throw InputError(origin, "relic", "one of " + relicNameList() + " or a .gltf/.glb path", name);
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

}  // namespace holo::relics
