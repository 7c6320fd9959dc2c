// The one place that maps directions to equirectangular panorama pixels and back.
//
// Convention (world = pyramid frame, +Y up): a panorama W x H covers longitude with u = x / W
// and colatitude with v = y / H (pixel centres at x + 0.5, y + 0.5).
//   v = acos(d.y) / pi                      (top row looks up, +Y; bottom row looks down)
//   u = 0.5 + atan2(d.x, -d.z) / (2 pi)     (image centre looks along -Z; u grows towards +X)
// So a viewer at the panorama centre facing -Z sees +X on their right, and the image shows +X to
// the right of its centre: left stays left, as in the real room. A calibrated yaw (radians,
// counter-clockwise about +Y seen from above) rotates the world before the lookup.
#pragma once

#include <opencv2/core.hpp>

#include "holo/core/math.hpp"

namespace holo::equirect {

vec2 directionToUv(const vec3& direction, float yaw = 0.0f);  // u, v in [0, 1]
vec3 uvToDirection(const vec2& uv, float yaw = 0.0f);         // unit direction
// The four pixels of a bilinear lookup at uv in a width x height panorama (wrapping in u,
// clamping in v) and the weights: (1 - fx) (1 - fy) at (x[0], y[0]) ... fx fy at (x[1], y[1]).
struct BilinearTaps {
  int x[2], y[2];
  float fx, fy;
};
BilinearTaps bilinearTaps(const vec2& uv, int width, int height);
// Bilinear lookup of a CV_32FC3 BGR panorama (wraps in u, clamps in v); returns RGB.
vec3 sample(const cv::Mat& panorama, const vec3& direction, float yaw = 0.0f);
// Solid angle of one pixel in row y (steradians): (2 pi / W) * (pi / H) * sin(theta).
float pixelSolidAngle(int y, int width, int height);

}  // namespace holo::equirect
