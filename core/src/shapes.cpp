#include "holo/core/shapes.hpp"

#include <algorithm>

namespace holo {
namespace {

// Two triangles per cell of a grid of `rows` rings of `segments` + 1 vertices (the seam's column
// duplicated for the uvs), facing outward for rings that go up +y around it.
void appendRingTriangles(TriangleMesh& m, int rows, int segments) {
  const int cols = segments + 1;
  for (int i = 0; i + 1 < rows; ++i)
    for (int j = 0; j < segments; ++j) {
      const auto a = static_cast<unsigned>(i * cols + j), b = a + 1, c = a + static_cast<unsigned>(cols),
                 d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
}

}  // namespace

TriangleMesh makeBox(const vec3& h) {
  TriangleMesh m;
  m.name = "box";
  // One quad per face so each face keeps its own flat normal.
  const vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const vec3& n : normals) {
    // Two tangents u, v with u x v = n.
    const vec3 u = std::abs(n.y) > 0.5f ? vec3(0, 0, n.y) : vec3(-n.z, 0, n.x);
    const vec3 v = glm::cross(n, u);
    const auto base = static_cast<unsigned>(m.positions.size());
    for (const vec2 c : {vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, 1)}) {
      m.positions.push_back((n + c.x * u + c.y * v) * h);
      m.normals.push_back(n);
      m.uvs.push_back(0.5f * (c + 1.0f));
    }
    // (u, v, n) is right-handed, so counter-clockwise seen from outside.
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
  }
  return m;
}

TriangleMesh makeLathe(const std::vector<vec2>& profile, int segments) {
  TriangleMesh m;
  m.name = "lathe";
  const int rows = static_cast<int>(profile.size());
  const int cols = segments + 1;  // seam duplicated for uvs
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const float a = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
      m.positions.push_back({profile[static_cast<std::size_t>(i)].x * std::sin(a),
                             profile[static_cast<std::size_t>(i)].y,
                             profile[static_cast<std::size_t>(i)].x * std::cos(a)});
      m.uvs.push_back({static_cast<float>(j) / static_cast<float>(segments),
                       rows > 1 ? static_cast<float>(i) / static_cast<float>(rows - 1) : 0.0f});
    }
  }
  appendRingTriangles(m, rows, segments);
  m.computeNormals();
  return m;
}

TriangleMesh makeEllipticSweep(const std::vector<EllipseRing>& rings, int segments) {
  TriangleMesh m;
  m.name = "sweep";
  const int rows = static_cast<int>(rings.size());
  const int cols = segments + 1;  // seam duplicated for uvs
  for (int i = 0; i < rows; ++i) {
    const EllipseRing& r = rings[static_cast<std::size_t>(i)];
    for (int j = 0; j < cols; ++j) {
      // The seam's copy takes angle 0 itself (sin 2 pi is not 0 in floats): watertight bit for bit.
      const float a =
          j == segments ? 0.0f : 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
      m.positions.push_back({r.half_x * std::sin(a), r.y, r.centre_z + r.half_z * std::cos(a)});
      m.uvs.push_back({static_cast<float>(j) / static_cast<float>(segments),
                       rows > 1 ? static_cast<float>(i) / static_cast<float>(rows - 1) : 0.0f});
    }
  }
  appendRingTriangles(m, rows, segments);
  m.computeNormals();
  // A closing point's copies each see only their own (degenerate-free) fan: give them one normal.
  for (int i : {0, rows - 1}) {
    const EllipseRing& r = rings[static_cast<std::size_t>(std::max(i, 0))];
    if (rows < 2 || r.half_x > 0.0f || r.half_z > 0.0f) continue;
    vec3 sum(0.0f);
    for (int j = 0; j < segments; ++j) sum += m.normals[static_cast<std::size_t>(i * cols + j)];
    const vec3 n = glm::length(sum) > 0.0f ? glm::normalize(sum) : vec3(0, i == 0 ? -1 : 1, 0);
    for (int j = 0; j < cols; ++j) m.normals[static_cast<std::size_t>(i * cols + j)] = n;
  }
  return m;
}

TriangleMesh makeCylinder(float radius, float height, int segments) {
  TriangleMesh m = makeLathe(
      {{0, 0}, {radius, 0}, {radius, 0}, {radius, height}, {radius, height}, {0, height}}, segments);
  m.name = "cylinder";
  // The duplicated rim rows make sharp edges: give the caps and the side their own normals.
  const int cols = segments + 1;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < cols; ++j) {
      auto& n = m.normals[static_cast<std::size_t>(i * cols + j)];
      if (i <= 1)
        n = {0, -1, 0};
      else if (i >= 4)
        n = {0, 1, 0};
      else
        n = glm::normalize(vec3(m.positions[static_cast<std::size_t>(i * cols + j)].x, 0,
                                m.positions[static_cast<std::size_t>(i * cols + j)].z));
    }
  return m;
}

TriangleMesh makeSphere(float radius, int rings, int segments) {
  std::vector<vec2> profile;
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPi * (1.0f - static_cast<float>(i) / static_cast<float>(rings));  // bottom to top
    profile.push_back({radius * std::sin(theta), radius * std::cos(theta)});
  }
  profile.front().x = 0.0f;
  profile.back().x = 0.0f;
  TriangleMesh m = makeLathe(profile, segments);
  m.name = "sphere";
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const float len = glm::length(m.positions[i]);
    if (len > 0) m.normals[i] = m.positions[i] / len;
  }
  return m;
}

TriangleMesh makeTube(const std::vector<vec3>& path, const std::vector<float>& radii, int segments) {
  TriangleMesh m;
  m.name = "tube";
  const std::size_t n = path.size();
  if (n < 2 || radii.size() != n) return m;
  // Parallel-transported frame so the tube does not twist.
  vec3 tangent = glm::normalize(path[1] - path[0]);
  vec3 normal = std::abs(tangent.y) < 0.9f ? glm::normalize(glm::cross(tangent, vec3(0, 1, 0)))
                                           : glm::normalize(glm::cross(tangent, vec3(1, 0, 0)));
  const int cols = segments + 1;
  for (std::size_t i = 0; i < n; ++i) {
    const vec3 next_tangent = glm::normalize(i + 1 < n ? path[i + 1] - path[i] : path[i] - path[i - 1]);
    const vec3 t = i == 0 ? tangent : glm::normalize(tangent + next_tangent);
    normal = glm::normalize(normal - glm::dot(normal, t) * t);
    const vec3 binormal = glm::cross(t, normal);
    for (int j = 0; j < cols; ++j) {
      const float a = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
      const vec3 dir = std::cos(a) * normal + std::sin(a) * binormal;
      m.positions.push_back(path[i] + radii[i] * dir);
      m.normals.push_back(dir);
      m.uvs.push_back({static_cast<float>(j) / static_cast<float>(segments),
                       static_cast<float>(i) / static_cast<float>(n - 1)});
    }
    tangent = next_tangent;
  }
  for (std::size_t i = 0; i + 1 < n; ++i)
    for (int j = 0; j < segments; ++j) {
      const auto a = static_cast<unsigned>(i * static_cast<std::size_t>(cols) + static_cast<std::size_t>(j)),
                 b = a + 1, c = a + static_cast<unsigned>(cols), d = c + 1;
      m.triangles.push_back({a, d, b});
      m.triangles.push_back({a, c, d});
    }
  return m;
}

void appendMesh(TriangleMesh& dst, const TriangleMesh& part, const mat4& T) {
  TriangleMesh p = part;
  p.transform(T);
  const auto base = static_cast<unsigned>(dst.positions.size());
  const bool with_uvs =
      (dst.positions.empty() || dst.uvs.size() == dst.positions.size()) && p.uvs.size() == p.positions.size();
  if (!with_uvs) dst.uvs.clear();
  dst.positions.insert(dst.positions.end(), p.positions.begin(), p.positions.end());
  if (p.normals.size() != p.positions.size()) p.computeNormals();
  dst.normals.insert(dst.normals.end(), p.normals.begin(), p.normals.end());
  if (with_uvs) dst.uvs.insert(dst.uvs.end(), p.uvs.begin(), p.uvs.end());
  for (const auto& t : p.triangles) dst.triangles.push_back(t + uvec3(base));
}

std::vector<vec2> smoothProfile(const std::vector<vec2>& c, int samples) {
  std::vector<vec2> out;
  const int n = static_cast<int>(c.size());
  if (n < 2) return c;
  auto at = [&](int i) { return c[static_cast<std::size_t>(std::clamp(i, 0, n - 1))]; };
  for (int i = 0; i + 1 < n; ++i) {
    const vec2 p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
    for (int s = 0; s < samples; ++s) {
      const float t = static_cast<float>(s) / static_cast<float>(samples);
      const float t2 = t * t, t3 = t2 * t;
      out.push_back(0.5f * ((2.0f * p1) + (-p0 + p2) * t + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * t2 +
                            (-p0 + 3.0f * p1 - 3.0f * p2 + p3) * t3));
    }
  }
  out.push_back(c.back());
  for (auto& p : out) p.x = std::max(p.x, 0.0f);
  return out;
}

}  // namespace holo
