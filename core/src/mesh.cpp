#include "holo/core/mesh.hpp"

namespace holo {

Bounds3 TriangleMesh::bounds() const {
  Bounds3 b;
  for (const auto& p : positions) b.extend(p);
  return b;
}

void TriangleMesh::computeNormals() {
  normals.assign(positions.size(), vec3(0.0f));
  for (const auto& t : triangles) {
    const vec3 n = glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]);
    if (!isFinite(n)) continue;
    // The cross product's length is twice the area: summing unnormalised weights by area.
    for (int k = 0; k < 3; ++k) normals[t[k]] += n;
  }
  for (auto& n : normals) {
    const float len = glm::length(n);
    n = len > 1e-20f ? n / len : vec3(0, 1, 0);
  }
}

void TriangleMesh::transform(const mat4& T) {
  const mat3 N = glm::transpose(glm::inverse(mat3(T)));
  for (auto& p : positions) p = transformPoint(T, p);
  for (auto& n : normals) n = glm::normalize(N * n);
}

Bounds3 Model::bounds() const {
  Bounds3 b;
  for (const auto& m : meshes)
    for (const auto& p : m.positions) b.extend(p);
  return b;
}

std::size_t Model::triangleCount() const {
  std::size_t n = 0;
  for (const auto& m : meshes) n += m.triangles.size();
  return n;
}

void Model::transform(const mat4& T) {
  for (auto& m : meshes) m.transform(T);
}

}  // namespace holo
