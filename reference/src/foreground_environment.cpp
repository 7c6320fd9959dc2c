#include "holo/reference/foreground_environment.hpp"

#include <algorithm>
#include <cmath>

#include "equirect_disc.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::reference {

using reflect::forEachDiscPixel;

cv::Mat mergeForeground(const cv::Mat& static_panorama, const depthfilter::ForegroundCloud& cloud,
                        const vec3& centre, float point_radius, float yaw, ReprojectionStats* stats) {
  if (static_panorama.empty() || static_panorama.type() != CV_32FC3)
    throw InputError("", "panorama", "a non-empty CV_32FC3 linear BGR image");
  cv::Mat out = static_panorama.clone();
  const int w = out.cols, h = out.rows;
  cv::Mat depth(h, w, CV_32FC1, cv::Scalar(std::numeric_limits<float>::infinity()));
  ReprojectionStats st;
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
    // The point's disc: its physical radius seen from the centre.
    forEachDiscPixel(d / dist, std::atan(std::max(point_radius, 0.0f) / dist), w, h, yaw, [&](int x, int y) {
      float& z = depth.at<float>(y, x);
      if (dist < z) {
        if (std::isinf(z)) ++st.pixels_covered;
        z = dist;
        setRgb(out, x, y, phi * colour + (1.0f - phi) * rgbAt(static_panorama, x, y));
      }
    });
  }
  if (stats) *stats = st;
  return out;
}

}  // namespace holo::reference
