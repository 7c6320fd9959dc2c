#include "holo/sim/halls.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <map>

#include "holo/core/error.hpp"
#include "holo/core/shapes.hpp"

namespace holo::sim {

namespace {

constexpr float kFloor = -kBaseHeight;

mat4 at(const vec3& p) {
  return glm::translate(mat4(1.0f), p);
}

// The hall's shiny parts. Only the depth sensor model reads metallic and roughness (a camera,
// the panorama and the path tracer see every hall surface as its emission, museum.hpp): gilt
// frames and bollard tops, steel poles and the lacquered bollards lose depth as on a real Kinect.
struct Finish {
  const char* material;
  float metallic;
  float roughness;
};
constexpr Finish kFinishes[] = {{"frame", 1.0f, 0.3f},
                                {"bollard_top", 1.0f, 0.15f},
                                {"info_pole", 1.0f, 0.35f},
                                {"lamp_pole", 1.0f, 0.35f},
                                {"bollard", 0.0f, 0.15f}};

// Collects parts into one mesh per material, so a hall is a handful of Embree geometries.
class HallBuilder {
 public:
  void add(const std::string& material, const vec3& radiance, const TriangleMesh& part,
           const mat4& T = mat4(1.0f)) {
    auto [it, inserted] = index_.try_emplace(material, static_cast<int>(model_.materials.size()));
    if (inserted) {
      Material m;
      m.name = material;
      // The base colour is the radiance's chromaticity, for renderers that want an albedo.
      m.base_colour =
          glm::clamp(radiance / std::max(1.0f, std::max({radiance.r, radiance.g, radiance.b})), 0.0f, 1.0f);
      m.roughness = 1.0f;
      for (const Finish& f : kFinishes)
        if (material == f.material) {
          m.metallic = f.metallic;
          m.roughness = f.roughness;
        }
      m.emission = radiance;
      model_.materials.push_back(m);
      TriangleMesh mesh;
      mesh.name = material;
      mesh.material = it->second;
      model_.meshes.push_back(std::move(mesh));
    }
    appendMesh(model_.meshes[static_cast<std::size_t>(it->second)], part, T);
  }
  // Box from corner lo to corner hi.
  void box(const std::string& material, const vec3& radiance, const vec3& lo, const vec3& hi) {
    add(material, radiance, makeBox(0.5f * (hi - lo)), at(0.5f * (lo + hi)));
  }
  // Floor, four walls and a ceiling, each wall its own material.
  void shell(float x0, float x1, float z0, float z1, float ceiling, const vec3& north, const vec3& south,
             const vec3& east, const vec3& west, const vec3& ceiling_radiance) {
    const float t = 0.1f;
    box("wall_north", north, {x0 - t, kFloor, z0 - t}, {x1 + t, ceiling, z0});
    box("wall_south", south, {x0 - t, kFloor, z1}, {x1 + t, ceiling, z1 + t});
    box("wall_east", east, {x1, kFloor, z0}, {x1 + t, ceiling, z1});
    box("wall_west", west, {x0 - t, kFloor, z0}, {x0, ceiling, z1});
    box("ceiling", ceiling_radiance, {x0 - t, ceiling, z0 - t}, {x1 + t, ceiling + t, z1 + t});
  }
  // A checkerboard floor of square tiles in two materials.
  void checkerFloor(float x0, float x1, float z0, float z1, float tile, const vec3& a, const vec3& b) {
    int i = 0;
    for (float x = x0; x < x1 - 1e-4f; x += tile, ++i) {
      int j = 0;
      for (float z = z0; z < z1 - 1e-4f; z += tile, ++j) {
        const bool dark = (i + j) % 2 == 1;
        box(dark ? "floor_dark" : "floor_light", dark ? b : a, {x, kFloor - 0.05f, z},
            {std::min(x + tile, x1), kFloor, std::min(z + tile, z1)});
      }
    }
  }
  void base() {
    box("pyramid_base", {0.03f, 0.03f, 0.035f}, {-kBaseHalfWidth, kFloor, -kBaseHalfWidth},
        {kBaseHalfWidth, 0.0f, kBaseHalfWidth});
  }
  Model take() { return std::move(model_); }

 private:
  Model model_;
  std::map<std::string, int> index_;
};

// Saturated colours for furniture, books and canvases (linear radiance).
const vec3 kRed{0.7f, 0.04f, 0.04f}, kYellow{0.85f, 0.7f, 0.05f}, kGreen{0.05f, 0.5f, 0.08f},
    kBlue{0.05f, 0.1f, 0.6f}, kMagenta{0.6f, 0.02f, 0.35f}, kCyan{0.02f, 0.45f, 0.55f},
    kOrange{0.85f, 0.3f, 0.02f}, kWood{0.2f, 0.11f, 0.05f}, kWhite{0.7f, 0.7f, 0.68f},
    kGold{0.9f, 0.6f, 0.1f};

Model room() {
  HallBuilder b;
  b.base();
  // Oak floorboards along X.
  for (int i = 0; i < 25; ++i) {
    const float z = -2.5f + 0.2f * static_cast<float>(i);
    const bool dark = i % 2 == 1;
    b.box(dark ? "floor_dark" : "floor_light", dark ? vec3(0.26f, 0.16f, 0.08f) : vec3(0.32f, 0.2f, 0.1f),
          {-2.5f, kFloor - 0.05f, z}, {2.5f, kFloor, z + 0.2f});
  }
  b.shell(-2.5f, 2.5f, -2.5f, 2.5f, 1.8f, {0.08f, 0.15f, 0.45f}, {0.6f, 0.55f, 0.45f}, {0.25f, 0.4f, 0.22f},
          {0.55f, 0.22f, 0.12f}, {0.45f, 0.45f, 0.42f});
  b.box("lamp_ceiling", {24.0f, 22.0f, 18.0f}, {-0.5f, 1.78f, -0.5f}, {0.5f, 1.8f, 0.5f});
  b.box("window", {6.0f, 7.0f, 9.0f}, {2.48f, 0.0f, -1.0f}, {2.5f, 1.2f, 0.5f});
  // Red sofa against the north wall.
  b.box("sofa", kRed, {-1.2f, kFloor, -2.45f}, {1.2f, -0.55f, -1.6f});
  b.box("sofa", kRed, {-1.2f, -0.55f, -2.45f}, {1.2f, 0.0f, -2.2f});
  b.box("sofa", kRed, {-1.4f, kFloor, -2.45f}, {-1.2f, -0.4f, -1.6f});
  b.box("sofa", kRed, {1.2f, kFloor, -2.45f}, {1.4f, -0.4f, -1.6f});
  // Bookcase on the west wall with books in saturated colours.
  b.box("bookcase", kWood, {-2.5f, kFloor, 0.2f}, {-2.15f, 1.0f, 1.8f});
  const vec3 books[] = {kRed, kYellow, kGreen, kBlue, kMagenta, kCyan, kOrange};
  for (int shelf = 0; shelf < 4; ++shelf) {
    const float y = kFloor + 0.1f + 0.5f * static_cast<float>(shelf);
    for (int k = 0; k < 12; ++k) {
      const float z = 0.3f + 0.12f * static_cast<float>(k);
      const int c = (k * 3 + shelf) % 7;
      b.box("book_" + std::to_string(c), books[c], {-2.14f, y, z},
            {-2.0f, y + 0.3f + 0.05f * static_cast<float>(k % 3), z + 0.09f});
    }
  }
  // Near the pyramid: a yellow side table (0.85 m) and a green plant (0.92 m).
  b.box("side_table", kYellow, {0.7f, -0.35f, 0.05f}, {1.1f, -0.3f, 0.45f});
  for (float dx : {0.72f, 1.06f})
    for (float dz : {0.07f, 0.41f})
      b.box("side_table", kYellow, {dx, kFloor, dz}, {dx + 0.03f, -0.35f, dz + 0.03f});
  b.add("flower_pot", {0.5f, 0.25f, 0.1f}, makeCylinder(0.15f, 0.4f), at({-0.55f, kFloor, -0.7f}));
  b.add("plant", kGreen, makeSphere(0.3f, 10, 16), at({-0.55f, kFloor + 0.7f, -0.7f}));
  // Floor lamp in a corner.
  b.add("lamp_pole", {0.05f, 0.05f, 0.05f}, makeCylinder(0.02f, 1.5f, 8), at({-2.0f, kFloor, 2.0f}));
  b.add("lamp_shade", {12.0f, 10.0f, 6.0f}, makeSphere(0.2f, 8, 16), at({-2.0f, kFloor + 1.6f, 2.0f}));
  return b.take();
}

Model gallery() {
  HallBuilder b;
  b.base();
  const float x0 = -8.0f, x1 = 8.0f, z0 = -2.8f, z1 = 2.8f, ceiling = 3.5f;
  b.checkerFloor(x0, x1, z0, z1, 0.8f, {0.45f, 0.43f, 0.4f}, {0.15f, 0.14f, 0.13f});
  b.shell(x0, x1, z0, z1, ceiling, {0.55f, 0.52f, 0.48f}, {0.5f, 0.5f, 0.47f}, {0.05f, 0.08f, 0.3f},
          {0.4f, 0.05f, 0.06f}, {0.35f, 0.35f, 0.35f});
  for (int i = 0; i < 8; ++i) {
    const float x = -7.0f + 2.0f * static_cast<float>(i);
    b.box("lamp_ceiling", {30.0f, 27.0f, 22.0f}, {x - 0.3f, ceiling - 0.02f, -0.15f},
          {x + 0.3f, ceiling, 0.15f});
  }
  // Paintings on both long walls: a gilt frame and a saturated canvas.
  const vec3 canvases[] = {kRed, kBlue, kYellow, kGreen, kMagenta, kCyan, kOrange, kBlue, kRed, kGreen};
  int k = 0;
  for (float x : {-6.0f, -3.0f, 0.0f, 3.0f, 6.0f}) {
    for (int side : {-1, 1}) {
      const float wall = side < 0 ? z0 : z1;
      const float d = side < 0 ? 1.0f : -1.0f;  // into the room
      b.box("frame", kGold, {x - 0.8f, 0.2f, std::min(wall, wall + d * 0.04f)},
            {x + 0.8f, 1.6f, std::max(wall, wall + d * 0.04f)});
      b.box("canvas_" + std::to_string(k % 7), canvases[k],
            {x - 0.7f, 0.3f, std::min(wall + d * 0.04f, wall + d * 0.06f)},
            {x + 0.7f, 1.5f, std::max(wall + d * 0.04f, wall + d * 0.06f)});
      ++k;
    }
  }
  // Benches in the middle of the gallery.
  for (float x : {-4.5f, 4.5f}) b.box("bench", kWood, {x - 0.9f, kFloor, -0.25f}, {x + 0.9f, -0.55f, 0.25f});
  // A white plinth with an orange sphere.
  b.box("plinth", kWhite, {-6.3f, kFloor, 1.2f}, {-5.7f, 0.1f, 1.8f});
  b.add("sculpture", kOrange, makeSphere(0.25f, 10, 20), at({-6.0f, 0.35f, 1.5f}));
  // Near the pyramid (0.95 m, on a diagonal between two cameras): a magenta information stand.
  b.add("info_pole", {0.05f, 0.05f, 0.05f}, makeCylinder(0.025f, 1.2f, 8), at({0.67f, kFloor, 0.67f}));
  b.box("info_panel", kMagenta, {0.5f, 0.2f, 0.62f}, {0.84f, 0.65f, 0.72f});
  return b.take();
}

Model atrium() {
  HallBuilder b;
  b.base();
  const float h = 6.0f, ceiling = 11.0f;
  b.checkerFloor(-h, h, -h, h, 1.5f, {0.5f, 0.5f, 0.48f}, {0.12f, 0.12f, 0.14f});
  b.shell(-h, h, -h, h, ceiling, {0.5f, 0.4f, 0.28f}, {0.48f, 0.39f, 0.27f}, {0.45f, 0.37f, 0.26f},
          {0.52f, 0.42f, 0.3f}, {0.3f, 0.3f, 0.32f});
  b.box("skylight", {40.0f, 42.0f, 48.0f}, {-2.0f, ceiling - 0.02f, -2.0f}, {2.0f, ceiling, 2.0f});
  for (float x : {-3.5f, 0.0f, 3.5f})
    b.box("window", {8.0f, 9.0f, 11.0f}, {x - 0.6f, 5.0f, -h}, {x + 0.6f, 9.0f, -h + 0.02f});
  // Eight columns on a circle of 4 m.
  for (int i = 0; i < 8; ++i) {
    const float a = 2.0f * kPi * (static_cast<float>(i) + 0.5f) / 8.0f;
    b.add("column", {0.55f, 0.5f, 0.42f}, makeCylinder(0.3f, ceiling - kFloor, 20),
          at({4.0f * std::sin(a), kFloor, 4.0f * std::cos(a)}));
  }
  // A balcony around the walls at y = 4 with a red railing, and hanging banners.
  b.box("balcony", {0.4f, 0.35f, 0.3f}, {-h, 3.8f, -h}, {h, 4.0f, -h + 1.2f});
  b.box("balcony", {0.4f, 0.35f, 0.3f}, {-h, 3.8f, h - 1.2f}, {h, 4.0f, h});
  b.box("railing", kRed, {-h, 4.0f, -h + 1.15f}, {h, 4.9f, -h + 1.2f});
  b.box("railing", kRed, {-h, 4.0f, h - 1.2f}, {h, 4.9f, h - 1.15f});
  const vec3 banners[] = {kMagenta, kCyan, kYellow, kGreen};
  for (int i = 0; i < 4; ++i) {
    const float x = -4.5f + 3.0f * static_cast<float>(i);
    b.box("banner_" + std::to_string(i), banners[i], {x - 0.5f, 0.8f, h - 1.25f},
          {x + 0.5f, 3.8f, h - 1.22f});
  }
  // Near the pyramid: four blue bollards with gold tops on the diagonals at 0.95 m.
  for (int i = 0; i < 4; ++i) {
    const float a = kPi * (0.25f + 0.5f * static_cast<float>(i));
    const vec3 p{0.95f * std::sin(a), kFloor, 0.95f * std::cos(a)};
    b.add("bollard", kBlue, makeCylinder(0.04f, 0.9f, 12), at(p));
    b.add("bollard_top", kGold, makeSphere(0.06f, 8, 12), at(p + vec3(0, 0.95f, 0)));
  }
  return b.take();
}

// A plain room whose light comes mostly through one tall window on the +Z wall, 2.2 m from the
// pyramid axis: the close visitor of the window scene (planCloseVisitors stands it in front of
// face 0) is between the window and the relic, so it shadows the relic and lends it its colour.
Model window() {
  HallBuilder b;
  b.base();
  const float x0 = -3.0f, x1 = 3.0f, z0 = -3.0f, z1 = 2.2f, ceiling = 2.0f;
  for (int i = 0; i < 26; ++i) {
    const float z = z0 + 0.2f * static_cast<float>(i);
    const bool dark = i % 2 == 1;
    b.box(dark ? "floor_dark" : "floor_light", dark ? vec3(0.12f, 0.09f, 0.06f) : vec3(0.16f, 0.12f, 0.08f),
          {x0, kFloor - 0.05f, z}, {x1, kFloor, std::min(z + 0.2f, z1)});
  }
  b.shell(x0, x1, z0, z1, ceiling, {0.18f, 0.17f, 0.16f}, {0.2f, 0.19f, 0.17f}, {0.17f, 0.18f, 0.2f},
          {0.2f, 0.17f, 0.15f}, {0.22f, 0.22f, 0.21f});
  // Daylight through the window, from knee height to above a visitor's head.
  b.box("window", {9.0f, 10.0f, 11.5f}, {-0.9f, -0.7f, z1 - 0.02f}, {0.9f, 1.5f, z1});
  b.box("window_frame", {0.05f, 0.05f, 0.05f}, {-0.95f, -0.75f, z1 - 0.03f}, {0.95f, -0.7f, z1});
  b.box("window_frame", {0.05f, 0.05f, 0.05f}, {-0.95f, 1.5f, z1 - 0.03f}, {0.95f, 1.55f, z1});
  // A dim lamp in the far corner and a grey bench against the west wall.
  b.add("lamp_shade", {3.0f, 2.6f, 1.8f}, makeSphere(0.15f, 8, 16), at({-2.6f, 1.5f, -2.6f}));
  b.box("bench", {0.25f, 0.24f, 0.22f}, {-2.9f, kFloor, -1.0f}, {-2.5f, -0.55f, 1.0f});
  return b.take();
}

}  // namespace

std::vector<std::string> hallNames() {
  return {"room", "gallery", "atrium", "window", "none"};
}

Model makeHall(const std::string& name, const std::string& origin) {
  if (name == "room") return room();
  if (name == "gallery") return gallery();
  if (name == "atrium") return atrium();
  if (name == "window") return window();
  if (name == "none") return {};
  throw InputError(origin, "hall", "one of room, gallery, atrium, window, none", name);
}

}  // namespace holo::sim
