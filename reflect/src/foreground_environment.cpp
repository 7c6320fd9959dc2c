#include "holo/reflect/foreground_environment.hpp"

#include <algorithm>
#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::reflect {

cv::Mat mergeForeground(const cv::Mat& static_panorama, const depthfilter::ForegroundCloud& cloud,
                        const vec3& centre, float point_radius, float yaw, ReprojectionStats* stats) {
  if (static_panorama.empty() || static_panorama.type() != CV_32FC3)
    throw InputError("", "panorama", "a non-empty CV_32FC3 linear BGR image");
  cv::Mat out = static_panorama.clone();
  const int w = out.cols, h = out.rows;
  cv::Mat depth(h, w, CV_32FC1, cv::Scalar(std::numeric_limits<float>::infinity()));
  ReprojectionStats st;
  const float row_angle = kPi / float(h), col_angle = 2.0f * kPi / float(w);
  for (const depthfilter::ForegroundPoint& point : cloud.points) {
    const vec3 d = point.position - centre;
    const float dist = glm::length(d);
    // The cloud's invariant says finite; a broken producer still must not poison the map.
    if (!isFinite(d) || !(dist > 1e-6f) || !isFinite(point.radiance) || !(point.weight > 0.0f)) {
      ++st.points_rejected;
      continue;
    }
    ++st.points_used;
    const vec3 colour = glm::max(point.radiance, vec3(0.0f));
    const float phi = std::min(point.weight, 1.0f);
    const vec2 uv = equirect::directionToUv(d / dist, yaw);
    const int cx = std::clamp(int(uv.x * float(w)), 0, w - 1);
    const int cy = std::clamp(int(uv.y * float(h)), 0, h - 1);
    // Angular radius of the point's disc, in rows and (latitude-stretched) columns.
    const float angle = std::atan(std::max(point_radius, 0.0f) / dist);
    const int ry = std::min(h / 2, int(std::ceil(angle / row_angle - 0.5f)));
    const float sin_theta = std::max(std::sin((float(cy) + 0.5f) * row_angle), 1e-3f);
    const int rx = std::min(w / 2, int(std::ceil(angle / (col_angle * sin_theta) - 0.5f)));
    for (int dy = -ry; dy <= ry; ++dy) {
      const int y = cy + dy;
      if (y < 0 || y >= h) continue;
      for (int dx = -rx; dx <= rx; ++dx) {
        const int x = ((cx + dx) % w + w) % w;
        float& z = depth.at<float>(y, x);
        if (dist < z) {
          if (std::isinf(z)) ++st.pixels_covered;
          z = dist;
          setRgb(out, x, y, phi * colour + (1.0f - phi) * rgbAt(static_panorama, x, y));
        }
      }
    }
  }
  if (stats) *stats = st;
  return out;
}

}  // namespace holo::reflect
