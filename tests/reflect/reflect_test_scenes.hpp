// Small analytic scenes shared by the reflect tests and benchmarks.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "holo/core/mesh.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/view.hpp"

namespace holo::test {

// A UV sphere with exact (analytic) normals and one material.
inline Model sphereModel(const reflect::SurfaceMaterial& m, float radius = 1.0f, vec3 centre = vec3(0.0f),
                         int stacks = 48, int slices = 96) {
  TriangleMesh mesh;
  mesh.name = "sphere";
  for (int i = 0; i <= stacks; ++i) {
    const float theta = kPi * float(i) / float(stacks);
    for (int j = 0; j <= slices; ++j) {
      const float phi = 2.0f * kPi * float(j) / float(slices);
      const vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      mesh.positions.push_back(centre + radius * n);
      mesh.normals.push_back(n);
    }
  }
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const unsigned a = unsigned(i * (slices + 1) + j), b = a + unsigned(slices + 1);
      mesh.triangles.push_back({a, a + 1, b});
      mesh.triangles.push_back({a + 1, b + 1, b});
    }
  Model model;
  model.meshes.push_back(mesh);
  Material mat;
  mat.base_colour = m.base_colour;
  mat.metallic = m.metallic;
  mat.roughness = m.roughness;
  model.materials.push_back(mat);
  return model;
}

// A square emitter of side `size` centred at `centre`, facing `normal`.
inline Model emitterQuad(const vec3& centre, const vec3& normal, float size, const vec3& radiance) {
  const vec3 n = glm::normalize(normal);
  const vec3 t = glm::normalize(glm::cross(std::abs(n.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0), n));
  const vec3 b = glm::cross(n, t);
  TriangleMesh mesh;
  mesh.name = "emitter";
  const float s = 0.5f * size;
  mesh.positions = {centre - s * t - s * b, centre + s * t - s * b, centre + s * t + s * b,
                    centre - s * t + s * b};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  Model model;
  model.meshes.push_back(mesh);
  Material mat;
  mat.emission = radiance;
  model.materials.push_back(mat);
  return model;
}

// A wall of red foreground points (radiance (2, 0, 0), weight 1) in the plane z = 0.6 on a 1 cm
// grid of columns x rows points from (x0, y0), and the one camera that sees it: at (0, 0.3, -0.2)
// behind a relic at (0, 0.3, 0), looking at the wall (64 x 64, vertical field of view 100
// degrees), its image the wall's red everywhere. Seen from +z, the wall stands between the relic
// and the viewer and appears only in reflections.
struct RedWall {
  reflect::ForegroundCameraImage camera;
  depthfilter::ForegroundCloud cloud;
};
inline RedWall redWall(float x0 = -0.4f, float y0 = -0.1f, int columns = 81, int rows = 81) {
  RedWall wall;
  wall.camera.camera = reflect::lookAtCamera(vec3(0.0f, 0.3f, -0.2f), vec3(0.0f, 0.3f, 0.6f), 100.0f, 64, 64);
  wall.camera.colour_bgr = cv::Mat(64, 64, CV_32FC3, cv::Scalar(0, 0, 2));  // red, linear BGR
  wall.camera.mask = cv::Mat(64, 64, CV_32FC1, cv::Scalar(1));
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < rows; ++j) {
      depthfilter::ForegroundPoint p;
      p.position = vec3(x0 + 0.01f * float(i), y0 + 0.01f * float(j), 0.6f);
      p.radiance = vec3(2.0f, 0.0f, 0.0f);
      const auto px = wall.camera.camera.project(p.position);
      p.x = std::uint16_t(std::clamp(px ? px->x : 0.0f, 0.0f, 63.0f));
      p.y = std::uint16_t(std::clamp(px ? px->y : 0.0f, 0.0f, 63.0f));
      wall.cloud.points.push_back(p);
    }
  return wall;
}

// Tracer settings whose voxel grid covers the test scenes' 2 x 1.5 x 2 m around the origin with
// 2 cm voxels (bricks of 4 voxels: 8 cm).
inline reflect::TracerSettings smallGrid() {
  reflect::TracerSettings s;
  s.grid.bounds = {vec3(-1.0f, 0.0f, -1.0f), vec3(1.0f, 1.5f, 1.0f)};
  s.grid.voxel_size = 0.02f;
  return s;
}

}  // namespace holo::test
