// Pinhole camera with OpenCV's five-parameter Brown-Conrady distortion and a pose.
// Units: pixels for intrinsics (pixel centres at integer coordinates, as OpenCV), metres for
// depth and poses. Depth is the camera-frame Z (not the distance along the ray), as depth cameras
// and OpenCV report it. Invariant: width, height > 0, fx, fy > 0, T_world_camera rigid.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "holo/core/math.hpp"

namespace holo {

struct Intrinsics {
  int width = 0;
  int height = 0;
  float fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<float, 5> distortion{};  // k1, k2, p1, p2, k3 (OpenCV order)

  // Ideal pinhole intrinsics from a horizontal and vertical field of view (radians).
  static Intrinsics fromFov(int width, int height, float hfov, float vfov);
  bool hasDistortion() const;
};

class CameraModel {
 public:
  CameraModel() = default;
  CameraModel(const Intrinsics& intrinsics, const mat4& T_world_camera);

  const Intrinsics& intrinsics() const { return K_; }
  int width() const { return K_.width; }
  int height() const { return K_.height; }
  const mat4& T_world_camera() const { return T_world_camera_; }
  const mat4& T_camera_world() const { return T_camera_world_; }
  vec3 position() const { return vec3(T_world_camera_[3]); }
  void setPose(const mat4& T_world_camera);

  // Camera-frame point -> distorted pixel. nullopt when the point is behind the camera (z <= 0).
  std::optional<vec2> projectCamera(const vec3& p_camera) const;
  // World point -> distorted pixel; also gives the camera-frame depth (z) when requested.
  std::optional<vec2> project(const vec3& p_world, float* depth = nullptr) const;

  // Distorted pixel -> normalised camera-frame direction with z = 1 (undistorts iteratively,
  // OpenCV's algorithm via cv::undistortPoints).
  vec3 unprojectToPlane(const vec2& pixel) const;
  // Distorted pixel and camera-frame depth (z, metres) -> world point.
  vec3 unproject(const vec2& pixel, float depth) const;
  // World-space ray through a pixel (unit direction, origin at the camera centre).
  Ray ray(const vec2& pixel) const;

  // Per-pixel z=1 directions for the whole image, row-major (computed in one OpenCV call);
  // back-projecting a depth image is then a multiply per pixel.
  std::vector<vec3> planeDirectionTable() const;

 private:
  Intrinsics K_;
  mat4 T_world_camera_{1.0f};
  mat4 T_camera_world_{1.0f};
};

}  // namespace holo
