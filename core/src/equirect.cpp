#include "holo/core/equirect.hpp"

#include <algorithm>

#include "holo/core/image.hpp"

namespace holo::equirect {

namespace {
vec3 rotateYaw(const vec3& d, float yaw) {
  const float c = std::cos(yaw), s = std::sin(yaw);
  return {c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
}
}  // namespace

vec2 directionToUv(const vec3& direction, float yaw) {
  const vec3 d = yaw != 0.0f ? rotateYaw(direction, -yaw) : direction;
  const float u = 0.5f + std::atan2(d.x, -d.z) / (2.0f * kPi);
  const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi;
  return {u - std::floor(u), v};
}

vec3 uvToDirection(const vec2& uv, float yaw) {
  const float phi = (uv.x - 0.5f) * 2.0f * kPi;
  const float theta = uv.y * kPi;
  const float st = std::sin(theta);
  const vec3 d(st * std::sin(phi), std::cos(theta), -st * std::cos(phi));
  return yaw != 0.0f ? rotateYaw(d, yaw) : d;
}

BilinearTaps bilinearTaps(const vec2& uv, int width, int height) {
  const float x = uv.x * float(width) - 0.5f;
  const float y = std::clamp(uv.y * float(height) - 0.5f, 0.0f, float(height - 1));
  const int x0 = static_cast<int>(std::floor(x));
  const int y0 = static_cast<int>(y);
  const int xa = (x0 % width + width) % width;
  return {{xa, (xa + 1) % width}, {y0, std::min(y0 + 1, height - 1)}, x - float(x0), y - float(y0)};
}

vec3 sample(const cv::Mat& panorama, const vec3& direction, float yaw) {
  const BilinearTaps t = bilinearTaps(directionToUv(direction, yaw), panorama.cols, panorama.rows);
  return (1 - t.fy) *
             ((1 - t.fx) * rgbAt(panorama, t.x[0], t.y[0]) + t.fx * rgbAt(panorama, t.x[1], t.y[0])) +
         t.fy * ((1 - t.fx) * rgbAt(panorama, t.x[0], t.y[1]) + t.fx * rgbAt(panorama, t.x[1], t.y[1]));
}

float pixelSolidAngle(int y, int width, int height) {
  const float theta = (float(y) + 0.5f) / float(height) * kPi;
  return (2.0f * kPi / float(width)) * (kPi / float(height)) * std::sin(theta);
}

}  // namespace holo::equirect
