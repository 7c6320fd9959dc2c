#include "holo/core/math.hpp"

namespace holo {

mat4 lookAtCameraToWorld(const vec3& eye, const vec3& target, const vec3& world_up) {
  const vec3 z = glm::normalize(target - eye);
  vec3 x = glm::cross(z, world_up);  // right = forward x up; then down = forward x right
  if (glm::dot(x, x) < 1e-12f) x = glm::cross(z, vec3(0, 0, 1));  // looking straight up/down
  x = glm::normalize(x);
  const vec3 y = glm::cross(z, x);
  mat4 T(1.0f);
  T[0] = vec4(x, 0);
  T[1] = vec4(y, 0);
  T[2] = vec4(z, 0);
  T[3] = vec4(eye, 1);
  return T;
}

}  // namespace holo
