#include "holo/ar/depth_surface.hpp"

#include <cmath>

#include "holo/core/error.hpp"

namespace holo::ar {

DepthSurface depthSurface(const cv::Mat& depth, const CameraModel& camera,
                          const DepthSurfaceSettings& settings, const std::string& camera_name) {
  if (depth.type() != CV_32FC1 || depth.cols != camera.width() || depth.rows != camera.height())
    throw InputError(camera_name, "depth",
                     "a CV_32FC1 depth image in metres of the camera's size " +
                         std::to_string(camera.width()) + "x" + std::to_string(camera.height()));
  const int w = depth.cols, h = depth.rows;
  std::vector<int> vertex(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), -1);
  DepthSurface out;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float z = depth.at<float>(y, x);
      if (!(z > 0.0f) || !std::isfinite(z)) continue;
      const vec3 p = camera.unproject({static_cast<float>(x), static_cast<float>(y)}, z);
      if (glm::length(p - settings.centre) > settings.radius) continue;
      vertex[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + x] =
          static_cast<int>(out.mesh.positions.size());
      out.mesh.positions.push_back(p);
      out.pixels.push_back({x, y});
    }
  const auto connected = [&](int x0, int y0, int x1, int y1) {
    const float a = depth.at<float>(y0, x0), b = depth.at<float>(y1, x1);
    return std::abs(a - b) <= settings.max_depth_step * std::min(a, b);
  };
  for (int y = 0; y + 1 < h; ++y)
    for (int x = 0; x + 1 < w; ++x) {
      const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
      const int a = vertex[row + x], b = vertex[row + x + 1], c = vertex[row + w + x],
                d = vertex[row + w + x + 1];
      // Camera winding (x right, y down) faces the camera: a, c, b and b, c, d.
      if (a >= 0 && b >= 0 && c >= 0 && connected(x, y, x + 1, y) && connected(x, y, x, y + 1) &&
          connected(x + 1, y, x, y + 1))
        out.mesh.triangles.push_back(
            {static_cast<unsigned>(a), static_cast<unsigned>(c), static_cast<unsigned>(b)});
      if (b >= 0 && c >= 0 && d >= 0 && connected(x + 1, y, x + 1, y + 1) &&
          connected(x, y + 1, x + 1, y + 1) && connected(x + 1, y, x, y + 1))
        out.mesh.triangles.push_back(
            {static_cast<unsigned>(b), static_cast<unsigned>(c), static_cast<unsigned>(d)});
    }
  out.mesh.name = camera_name + " depth";
  out.mesh.computeNormals();
  return out;
}

}  // namespace holo::ar
