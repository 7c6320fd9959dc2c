#include "holo/core/mesh.hpp"

#include <algorithm>

namespace holo {

namespace {

// A unit vector orthogonal to unit n (Duff et al. 2017, "Building an orthonormal basis,
// revisited"): the tangent of a vertex whose uvs say nothing.
vec3 anyTangent(const vec3& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  return {1.0f + sign * n.x * n.x * a, sign * n.x * n.y * a, -sign * n.x};
}

// Angle at corner p0 of the triangle (p0, p1, p2); 0 when an edge has no length.
float cornerAngle(const vec3& p0, const vec3& p1, const vec3& p2) {
  const vec3 a = p1 - p0, b = p2 - p0;
  const float la = glm::length(a), lb = glm::length(b);
  if (!(la > 0.0f) || !(lb > 0.0f)) return 0.0f;
  return std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0f, 1.0f));
}

}  // namespace

vec2 TextureRef::transform(vec2 uv) const {
  const float c = std::cos(rotation), s = std::sin(rotation);
  const vec2 scaled = uv * scale;
  // KHR_texture_transform's matrix: rotation R = [c s; -s c] applied to column vectors.
  return offset + vec2(c * scaled.x + s * scaled.y, -s * scaled.x + c * scaled.y);
}

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

// The MikkTSpace construction (Mikkelsen 2008, "Simulation of wrinkled surfaces revisited", the
// tangent space glTF 2.0 specifies for normal maps): each triangle's tangent and bitangent are
// the surface derivatives dP/du and dP/dv solved from its edges and uv differences; at each
// corner they are projected into the plane of the vertex normal, normalised and weighted by the
// corner's angle; a vertex sums its corners, is orthonormalised against its normal, and w is the
// handedness of (normal, tangent, bitangent). Triangles with zero uv area or no area contribute
// nothing. Unlike MikkTSpace this does not split a vertex shared by mirrored and unmirrored
// triangles: it takes the handedness of the larger summed weight.
void TriangleMesh::computeTangents(int tex_coord) {
  const std::vector<vec2>& uv = tex_coord == 1 ? uvs1 : uvs;
  const std::size_t n = positions.size();
  if (normals.size() != n) computeNormals();
  std::vector<vec3> tangent_sum(n, vec3(0.0f)), bitangent_sum(n, vec3(0.0f));
  if (uv.size() == n) {
    for (const auto& t : triangles) {
      const vec3 e1 = positions[t.y] - positions[t.x], e2 = positions[t.z] - positions[t.x];
      const vec2 d1 = uv[t.y] - uv[t.x], d2 = uv[t.z] - uv[t.x];
      const float det = d1.x * d2.y - d2.x * d1.y;
      if (!std::isfinite(det) || std::abs(det) < 1e-20f) continue;
      const vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det;
      const vec3 dpdv = (e2 * d1.x - e1 * d2.x) / det;
      if (!isFinite(dpdu) || !isFinite(dpdv)) continue;
      for (int k = 0; k < 3; ++k) {
        const unsigned v = t[k];
        const float angle =
            cornerAngle(positions[t[k]], positions[t[(k + 1) % 3]], positions[t[(k + 2) % 3]]);
        const vec3& nv = normals[v];
        const vec3 tp = dpdu - nv * glm::dot(nv, dpdu);
        const vec3 bp = dpdv - nv * glm::dot(nv, dpdv);
        const float lt = glm::length(tp), lb = glm::length(bp);
        if (lt > 1e-20f) tangent_sum[v] += angle * tp / lt;
        if (lb > 1e-20f) bitangent_sum[v] += angle * bp / lb;
      }
    }
  }
  tangents.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const vec3& nv = normals[i];
    vec3 t = tangent_sum[i] - nv * glm::dot(nv, tangent_sum[i]);
    const float len = glm::length(t);
    if (std::isfinite(len) && len > 1e-12f) {
      t /= len;
    } else {
      t = anyTangent(nv);
    }
    const float w = glm::dot(glm::cross(nv, t), bitangent_sum[i]) < 0.0f ? -1.0f : 1.0f;
    tangents[i] = vec4(t, w);
  }
}

void TriangleMesh::transform(const mat4& T) {
  const mat3 M(T);
  const mat3 N = glm::transpose(glm::inverse(M));
  const float handedness = glm::determinant(M) < 0.0f ? -1.0f : 1.0f;
  for (auto& p : positions) p = transformPoint(T, p);
  for (auto& n : normals) n = glm::normalize(N * n);
  for (std::size_t i = 0; i < tangents.size(); ++i) {
    vec3 t = M * vec3(tangents[i]);
    // A shear moves the tangent off the plane of the transformed normal: project it back.
    if (i < normals.size()) t -= normals[i] * glm::dot(normals[i], t);
    const float len = glm::length(t);
    const vec3 unit = len > 1e-20f ? t / len : (i < normals.size() ? anyTangent(normals[i]) : vec3(1, 0, 0));
    tangents[i] = vec4(unit, tangents[i].w * handedness);
  }
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
