// The AR tests' and benchmark's scene: a grey plane (y = 0) and a sphere standing on it, under a
// dim sky with one small bright sun, so the sphere casts a sharp shadow; a camera looking at both.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/gtc/constants.hpp>

#include "holo/ar/local_path_tracing.hpp"
#include "holo/ar/local_scene.hpp"
#include "holo/core/camera_model.hpp"
#include "holo/core/equirect.hpp"
#include "holo/core/image.hpp"
#include "holo/core/shapes.hpp"

namespace holo::ar::test {

inline constexpr float kPlaneAlbedo = 0.5f;

// 64x32 panorama: sky 0.3, ground 0.1, a sun of 4 pixels of radiance 400 in the +X sky, 38 degrees up.
inline cv::Mat sunnyPanorama() {
  cv::Mat pano(32, 64, CV_32FC3);
  for (int y = 0; y < pano.rows; ++y)
    for (int x = 0; x < pano.cols; ++x) setRgb(pano, x, y, vec3(y < pano.rows / 2 ? 0.3f : 0.1f));
  const vec3 sun = glm::normalize(vec3(1.0f, 0.8f, 0.1f));
  const vec2 uv = equirect::directionToUv(sun);
  const int sx = static_cast<int>(uv.x * pano.cols), sy = static_cast<int>(uv.y * pano.rows);
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx)
      setRgb(pano, (sx + dx) % pano.cols, std::min(sy + dy, pano.rows - 1), vec3(400.0f));
  return pano;
}

inline RealSurface plane() {
  RealSurface s;
  s.mesh.positions = {{-1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, 1.0f}, {-1.0f, 0.0f, 1.0f}};
  s.mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
  s.mesh.normals.assign(4, vec3(0.0f, 1.0f, 0.0f));
  s.albedo.assign(4, vec3(kPlaneAlbedo));
  return s;
}

inline Model sphereRelic() {
  Model m;
  TriangleMesh sphere = makeSphere(0.12f, 16, 32);
  for (vec3& p : sphere.positions) p += vec3(0.0f, 0.12f, 0.0f);
  m.meshes.push_back(sphere);
  Material material;
  material.base_colour = vec3(0.8f, 0.3f, 0.2f);
  material.roughness = 0.4f;
  m.materials.push_back(material);
  return m;
}

inline CameraModel camera(int width = 48, int height = 32) {
  const float vfov = glm::radians(50.0f);
  const float hfov =
      2.0f * std::atan(std::tan(0.5f * vfov) * static_cast<float>(width) / static_cast<float>(height));
  return CameraModel(Intrinsics::fromFov(width, height, hfov, vfov),
                     lookAtCameraToWorld({0.0f, 0.7f, 0.8f}, {-0.1f, 0.0f, -0.1f}));
}

// Sampling settings of a composite or a local scene's render: spp samples a pixel, seeded.
inline CompositeSettings samples(int spp, std::uint64_t seed, DifferentialMethod method = {}) {
  CompositeSettings s;
  s.method = method;
  s.spp = spp;
  s.seed = seed;
  return s;
}

// Rec. 709 luminance of linear RGB.
inline float luminance(const vec3& c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

}  // namespace holo::ar::test
