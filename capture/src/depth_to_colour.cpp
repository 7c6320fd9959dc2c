#include "holo/capture/depth_to_colour.hpp"

#include <cmath>

#include "holo/core/error.hpp"

namespace holo::capture {

DepthToColour::DepthToColour(const Intrinsics& depth, const Intrinsics& colour, const mat4& T_colour_depth)
    : depth_(depth), colour_(colour, mat4(1.0f)), T_colour_depth_(T_colour_depth) {
  if (depth.width <= 0 || depth.height <= 0 || colour.width <= 0 || colour.height <= 0)
    throw InputError("depth registration", "intrinsics", "positive image sizes for depth and colour");
  directions_ = CameraModel(depth, mat4(1.0f)).planeDirectionTable();
}

cv::Mat DepthToColour::apply(const cv::Mat& depth) const {
  if (depth.type() != CV_32FC1 || depth.cols != depth_.width || depth.rows != depth_.height)
    throw Error("depth registration: expected " + std::to_string(depth_.width) + "x" +
                std::to_string(depth_.height) + " CV_32FC1 depth, got " + std::to_string(depth.cols) + "x" +
                std::to_string(depth.rows) + " type " + std::to_string(depth.type()));
  cv::Mat out(colour_.height(), colour_.width(), CV_32FC1, cv::Scalar(0.0f));
  for (int y = 0; y < depth.rows; ++y) {
    const float* z = depth.ptr<float>(y);
    for (int x = 0; x < depth.cols; ++x) {
      if (!(z[x] > 0.0f) || !std::isfinite(z[x])) continue;
      const vec3 p_depth = directions_[static_cast<std::size_t>(y) * static_cast<std::size_t>(depth.cols) +
                                       static_cast<std::size_t>(x)] *
                           z[x];
      const vec3 p = transformPoint(T_colour_depth_, p_depth);
      const std::optional<vec2> pixel = colour_.projectCamera(p);
      if (!pixel) continue;
      // The 2x2 pixels around the landing point (pixel centres at integers).
      const int x0 = static_cast<int>(std::floor(pixel->x)), y0 = static_cast<int>(std::floor(pixel->y));
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int u = x0 + dx, v = y0 + dy;
          if (u < 0 || v < 0 || u >= out.cols || v >= out.rows) continue;
          float& target = out.at<float>(v, u);
          if (target == 0.0f || p.z < target) target = p.z;
        }
    }
  }
  return out;
}

}  // namespace holo::capture
