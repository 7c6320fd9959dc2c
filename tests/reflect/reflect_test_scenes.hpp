// Small analytic scenes shared by the reflect tests and benchmarks.
#pragma once

#include <cmath>

#include "holo/core/mesh.hpp"
#include "holo/reflect/bsdf.hpp"

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
  mat.base_color = m.base_color;
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

}  // namespace holo::test
