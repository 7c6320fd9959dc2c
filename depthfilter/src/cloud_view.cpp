#include "holo/depthfilter/cloud_view.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::depthfilter {

cv::Mat renderShiftedCloud(const cv::Mat& depth, const Intrinsics& K, const vec3& shift, float near_m,
                           float far_m) {
  if (depth.type() != CV_32FC1 || depth.cols != K.width || depth.rows != K.height)
    throw Error("renderShiftedCloud: expected CV_32FC1 depth of the intrinsics' size");
  const CameraModel source(K, mat4(1.0f));
  const std::vector<vec3> directions = source.planeDirectionTable();
  cv::Mat zbuffer(depth.size(), CV_32FC1, cv::Scalar(INFINITY));
  cv::Mat value(depth.size(), CV_8UC1, cv::Scalar(0));
  const float range = std::max(1e-3f, far_m - near_m);
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      const float d = depth.at<float>(y, x);
      if (!(d > 0.0f) || !std::isfinite(d)) continue;
      const vec3 p = directions[std::size_t(y) * std::size_t(depth.cols) + std::size_t(x)] * d - shift;
      if (p.z <= 0.05f) continue;
      const int u = static_cast<int>(std::lround(K.fx * p.x / p.z + K.cx));
      const int v = static_cast<int>(std::lround(K.fy * p.y / p.z + K.cy));
      const auto level = static_cast<std::uint8_t>(1 + 254 * std::clamp((d - near_m) / range, 0.0f, 1.0f));
      for (int dv = 0; dv < 2; ++dv)
        for (int du = 0; du < 2; ++du) {
          const int uu = u + du, vv = v + dv;
          if (uu < 0 || vv < 0 || uu >= depth.cols || vv >= depth.rows || zbuffer.at<float>(vv, uu) <= p.z)
            continue;
          zbuffer.at<float>(vv, uu) = p.z;
          value.at<std::uint8_t>(vv, uu) = level;
        }
    }
  cv::Mat picture;
  cv::applyColorMap(value, picture, cv::COLORMAP_TURBO);
  picture.setTo(cv::Scalar::all(0), value == 0);
  return picture;
}

}  // namespace holo::depthfilter
