// A virtual plinth under the relic: a square block whose top lies a gap below the relic's lowest
// point, centred under the relic, a diffuse (Lambert) surface of one albedo. A scene or an exhibit
// adds it with a `plinth:` section (absent: no plinth):
//
//   plinth:
//     half_width: 0.12      # metres, half the side of its square top, in [0.01, 2]
//     height: 0.3           # metres from its top down, in [0.005, 3]
//     gap: 0.0              # metres between the relic's lowest point and the top, in [0, 1]
//     albedo: 0.7           # one number or three (RGB, linear), each in [0, 1]
//
// The live renderer draws it (reflect/frame_renderer.hpp), the path-traced truth traces it as a
// relic surface (plinthModel). Units: metres, world (pyramid) frame, +Y up.
#pragma once

#include <optional>

#include "holo/core/config.hpp"
#include "holo/core/math.hpp"
#include "holo/core/mesh.hpp"

namespace holo {

struct PlinthSettings {
  float half_width = 0.12f;
  float height = 0.3f;
  float gap = 0.0f;
  vec3 albedo{0.7f};
};

// `node` is the `plinth` section; throws InputError naming the file and plinth.FIELD for an
// unknown key, a wrong type or a value out of range.
PlinthSettings parsePlinth(const ConfigNode& node);

// The plinth placed under a relic: an axis-aligned box.
struct PlinthBox {
  vec2 centre{0.0f};  // (x, z) of its vertical axis
  float half_width = 0.0f;
  float top = 0.0f;     // y of its top face
  float bottom = 0.0f;  // y of its bottom face, top - height
  vec3 albedo{0.7f};
  Bounds3 bounds() const {
    return {vec3(centre.x - half_width, bottom, centre.y - half_width),
            vec3(centre.x + half_width, top, centre.y + half_width)};
  }
};
// Under `relic_bounds` (not empty): centred on its (x, z) centre, top at its lowest y minus the gap.
PlinthBox placePlinth(const PlinthSettings& settings, const Bounds3& relic_bounds);

// Where a ray first meets the box from outside: the distance along the unit direction and the
// face's outward normal; nullopt when it misses or starts inside.
struct PlinthHit {
  float t = 0.0f;
  vec3 normal{0.0f, 1.0f, 0.0f};
};
std::optional<PlinthHit> intersectPlinth(const PlinthBox& box, const Ray& ray);

// The box as one flat-shaded mesh with a Lambert material (roughness 1, no specular, its albedo):
// what the path-traced truth appends to the relic's model (the new material and mesh last).
void appendPlinth(Model& model, const PlinthBox& box);

}  // namespace holo
