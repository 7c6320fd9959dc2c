#include "holo/reflect/view.hpp"

#include <algorithm>
#include <cmath>

namespace holo::reflect {

vec3 faceDirection(int face) {
  const float azimuth = float(((face % 4) + 4) % 4) * 0.5f * kPi;
  return {std::sin(azimuth), 0.0f, std::cos(azimuth)};
}

vec3 defaultFaceEye(int face, const Bounds3& relic_bounds, float floor_y) {
  const vec3 centre = relic_bounds.empty() ? vec3(0.0f) : relic_bounds.center();
  vec3 eye = vec3(centre.x, 0.0f, centre.z) + kDefaultEyeDistance * faceDirection(face);
  eye.y = floor_y + kDefaultEyeHeight;
  return eye;
}

CameraModel lookAtCamera(const vec3& eye, const vec3& target, float vfov_deg, int width, int height) {
  const float vfov = std::clamp(vfov_deg, 1.0f, 170.0f) * kPi / 180.0f;
  const float fy = 0.5f * float(height) / std::tan(0.5f * vfov);
  Intrinsics K;
  K.width = width;
  K.height = height;
  K.fx = K.fy = fy;
  K.cx = 0.5f * float(width) - 0.5f;
  K.cy = 0.5f * float(height) - 0.5f;
  return CameraModel(K, lookAtCameraToWorld(eye, target));
}

float framingFovDeg(const vec3& eye, const Bounds3& relic_bounds) {
  if (relic_bounds.empty()) return kDefaultFovDeg;
  const float radius = 0.5f * glm::length(relic_bounds.extent());
  const float distance = glm::length(relic_bounds.center() - eye);
  if (!(distance > radius)) return 120.0f;
  return std::min(120.0f, 2.0f * std::asin(radius / distance) * 180.0f / kPi * 1.1f);
}

Ray primaryRay(const CameraModel& camera, const vec2& pixel) {
  const Intrinsics& K = camera.intrinsics();
  if (K.hasDistortion()) return camera.ray(pixel);
  const vec3 d((pixel.x - K.cx) / K.fx, (pixel.y - K.cy) / K.fy, 1.0f);
  return {camera.position(), glm::normalize(transformDirection(camera.T_world_camera(), d))};
}

}  // namespace holo::reflect
