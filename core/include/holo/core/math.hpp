// Math vocabulary: GLM types, rays and rigid transforms.
// Units: metres and radians everywhere. Frames: world = pyramid frame (origin at the centre of
// the top plane of the base, +Y up); cameras follow OpenCV (+X right, +Y down, +Z forward).
// A transform named T_a_b maps coordinates in frame b to frame a (so T_world_camera takes a
// point from camera coordinates to world coordinates).
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

namespace holo {

using glm::ivec2;
using glm::mat3;
using glm::mat4;
using glm::uvec3;
using glm::vec2;
using glm::vec3;
using glm::vec4;

inline constexpr float kPi = 3.14159265358979323846f;

struct Ray {
  vec3 origin{0.0f};
  vec3 direction{0.0f, 0.0f, 1.0f};  // unit length
};

inline vec3 transformPoint(const mat4& T, const vec3& p) {
  return vec3(T * vec4(p, 1.0f));
}
inline vec3 transformDirection(const mat4& T, const vec3& d) {
  return mat3(T) * d;
}

// Inverse of a rigid transform (rotation + translation), exact and cheaper than glm::inverse.
inline mat4 rigidInverse(const mat4& T) {
  const mat3 Rt = glm::transpose(mat3(T));
  mat4 out(Rt);
  out[3] = vec4(-(Rt * vec3(T[3])), 1.0f);
  return out;
}

// Axis-aligned box; an empty box has lo > hi.
struct Bounds3 {
  vec3 lo{1e30f};
  vec3 hi{-1e30f};
  void extend(const vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  vec3 center() const { return 0.5f * (lo + hi); }
  vec3 extent() const { return hi - lo; }
};

inline bool isFinite(const vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

inline float maxComponent(const vec3& v) {
  return std::max({v.x, v.y, v.z});
}

inline float luminance(const vec3& rgb) {
  return 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b;
}

// A right-handed camera-to-world pose whose +Z axis looks from `eye` at `target`, with image
// +Y pointing as close to world -Y (down) as possible: the OpenCV convention.
mat4 lookAtCameraToWorld(const vec3& eye, const vec3& target, const vec3& world_up = {0, 1, 0});

}  // namespace holo
