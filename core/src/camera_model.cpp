#include "holo/core/camera_model.hpp"

#include <opencv2/calib3d.hpp>

#include "holo/core/error.hpp"

namespace holo {

Intrinsics Intrinsics::fromFov(int width, int height, float hfov, float vfov) {
  Intrinsics K;
  K.width = width;
  K.height = height;
  K.fx = 0.5f * static_cast<float>(width) / std::tan(0.5f * hfov);
  K.fy = 0.5f * static_cast<float>(height) / std::tan(0.5f * vfov);
  K.cx = 0.5f * static_cast<float>(width - 1);
  K.cy = 0.5f * static_cast<float>(height - 1);
  return K;
}

bool Intrinsics::hasDistortion() const {
  for (float k : distortion)
    if (k != 0.0f) return true;
  return false;
}

CameraModel::CameraModel(const Intrinsics& intrinsics, const mat4& T_world_camera) : K_(intrinsics) {
  if (K_.width <= 0 || K_.height <= 0 || !(K_.fx > 0) || !(K_.fy > 0))
    throw Error("camera model: image size and focal lengths must be positive");
  setPose(T_world_camera);
}

void CameraModel::setPose(const mat4& T_world_camera) {
  T_world_camera_ = T_world_camera;
  T_camera_world_ = rigidInverse(T_world_camera);
}

std::optional<vec2> CameraModel::projectCamera(const vec3& p) const {
  if (!(p.z > 0.0f)) return std::nullopt;
  const float x = p.x / p.z, y = p.y / p.z;
  const auto& d = K_.distortion;
  const float r2 = x * x + y * y;
  const float radial = 1.0f + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
  const float xd = x * radial + 2.0f * d[2] * x * y + d[3] * (r2 + 2.0f * x * x);
  const float yd = y * radial + d[2] * (r2 + 2.0f * y * y) + 2.0f * d[3] * x * y;
  return vec2(K_.fx * xd + K_.cx, K_.fy * yd + K_.cy);
}

std::optional<vec2> CameraModel::project(const vec3& p_world, float* depth) const {
  const vec3 p = transformPoint(T_camera_world_, p_world);
  if (depth) *depth = p.z;
  return projectCamera(p);
}

vec3 CameraModel::unprojectToPlane(const vec2& pixel) const {
  if (!K_.hasDistortion()) return {(pixel.x - K_.cx) / K_.fx, (pixel.y - K_.cy) / K_.fy, 1.0f};
  const cv::Matx33d K(K_.fx, 0, K_.cx, 0, K_.fy, K_.cy, 0, 0, 1);
  const cv::Vec<double, 5> dist(K_.distortion[0], K_.distortion[1], K_.distortion[2], K_.distortion[3],
                                K_.distortion[4]);
  std::vector<cv::Point2f> in{{pixel.x, pixel.y}}, out;
  // OpenCV's default of 5 iterations leaves ~1e-3 px error at wide-angle corners; 20 converges.
  cv::undistortPoints(in, out, K, dist, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 1e-8));
  return {out[0].x, out[0].y, 1.0f};
}

vec3 CameraModel::unproject(const vec2& pixel, float depth) const {
  return transformPoint(T_world_camera_, unprojectToPlane(pixel) * depth);
}

Ray CameraModel::ray(const vec2& pixel) const {
  return {position(), glm::normalize(transformDirection(T_world_camera_, unprojectToPlane(pixel)))};
}

std::vector<vec3> CameraModel::planeDirectionTable() const {
  const int n = K_.width * K_.height;
  std::vector<vec3> table(static_cast<std::size_t>(n));
  if (!K_.hasDistortion()) {
    for (int v = 0; v < K_.height; ++v)
      for (int u = 0; u < K_.width; ++u)
        table[static_cast<std::size_t>(v * K_.width + u)] = {(u - K_.cx) / K_.fx, (v - K_.cy) / K_.fy, 1.0f};
    return table;
  }
  std::vector<cv::Point2f> in(static_cast<std::size_t>(n)), out;
  for (int v = 0; v < K_.height; ++v)
    for (int u = 0; u < K_.width; ++u)
      in[static_cast<std::size_t>(v * K_.width + u)] = cv::Point2f(float(u), float(v));
  const cv::Matx33d K(K_.fx, 0, K_.cx, 0, K_.fy, K_.cy, 0, 0, 1);
  const cv::Vec<double, 5> dist(K_.distortion[0], K_.distortion[1], K_.distortion[2], K_.distortion[3],
                                K_.distortion[4]);
  cv::undistortPoints(in, out, K, dist, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 1e-8));
  for (std::size_t i = 0; i < out.size(); ++i) table[i] = {out[i].x, out[i].y, 1.0f};
  return table;
}

}  // namespace holo
