// A disc seen from an equirectangular image's centre: the pixels within about `angle` radians of
// a direction, as a box of rows and latitude-stretched columns around its pixel, wrapping in
// longitude. The paper's IBL reprojection (foreground_environment.cpp) and the rough foreground
// map (rough_foreground_map.cpp) splat with it, so that neighbouring points close up, also near
// the poles.
#pragma once

#include <algorithm>
#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/core/math.hpp"

namespace holo::reflect {

// Calls visit(x, y) for each pixel of the disc of `angle` radians (>= 0) around the unit
// `direction` in a width x height image (yaw as in core/equirect.hpp).
template <class Visit>
void forEachDiscPixel(const vec3& direction, float angle, int width, int height, float yaw, Visit&& visit) {
  const float row_angle = kPi / float(height), col_angle = 2.0f * kPi / float(width);
  const vec2 uv = equirect::directionToUv(direction, yaw);
  const int cx = std::clamp(int(uv.x * float(width)), 0, width - 1);
  const int cy = std::clamp(int(uv.y * float(height)), 0, height - 1);
  const int ry = std::min(height / 2, int(std::ceil(angle / row_angle - 0.5f)));
  const float sin_theta = std::max(std::sin((float(cy) + 0.5f) * row_angle), 1e-3f);
  const int rx = std::min(width / 2, int(std::ceil(angle / (col_angle * sin_theta) - 0.5f)));
  for (int dy = -ry; dy <= ry; ++dy) {
    const int y = cy + dy;
    if (y < 0 || y >= height) continue;
    for (int dx = -rx; dx <= rx; ++dx) visit(((cx + dx) % width + width) % width, y);
  }
}

}  // namespace holo::reflect
