#include "supporting_planes.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "holo/core/log.hpp"

namespace holo::reflect {
namespace {

// The relic's convex hull: its vertices and, per vertex, the hull vertices sharing a facet with it.
struct Hull {
  std::vector<vec3> vertices;
  std::vector<std::vector<std::uint32_t>> neighbours;
};

Hull convexHull(const std::vector<double>& points) {
  Hull hull;
  const int count = static_cast<int>(points.size() / 3);
  if (count < 4) return hull;
  qhT qh_storage;
  qhT* qh = &qh_storage;
  // Qhull reports degenerate input on its error stream; the caller logs the outcome itself.
  FILE* quiet = std::fopen("/dev/null", "w");
  qh_zero(qh, quiet);
  std::vector<double> copy = points;  // Qhull may scale its input
  char options[] = "qhull Qt";
  const int failed = qh_new_qhull(qh, 3, count, copy.data(), False, options, nullptr, quiet);
  if (!failed) {
    std::vector<int> index(static_cast<std::size_t>(qh->vertex_id) + 1, -1);
    vertexT* vertex = nullptr;
    FORALLvertices {
      index[vertex->id] = static_cast<int>(hull.vertices.size());
      hull.vertices.emplace_back(float(vertex->point[0]), float(vertex->point[1]), float(vertex->point[2]));
    }
    hull.neighbours.resize(hull.vertices.size());
    facetT* facet = nullptr;
    FORALLfacets {
      std::vector<std::uint32_t> corners;
      vertexT** vertexp = nullptr;
      FOREACHvertex_(facet->vertices) corners.push_back(static_cast<std::uint32_t>(index[vertex->id]));
      for (const std::uint32_t a : corners)
        for (const std::uint32_t b : corners)
          if (a != b) hull.neighbours[a].push_back(b);
    }
    for (auto& n : hull.neighbours) {
      std::sort(n.begin(), n.end());
      n.erase(std::unique(n.begin(), n.end()), n.end());
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int long_bytes = 0, total_bytes = 0;
  qh_memfreeshort(qh, &long_bytes, &total_bytes);
  if (quiet) std::fclose(quiet);
  if (failed) hull = {};
  return hull;
}

// The hull vertex farthest along `direction`, by ascent from `start` (updated to the answer).
float farthestAlong(const Hull& hull, const vec3& direction, std::uint32_t& start) {
  std::uint32_t at = start;
  float best = glm::dot(direction, hull.vertices[at]);
  for (bool moved = true; moved;) {
    moved = false;
    for (const std::uint32_t next : hull.neighbours[at]) {
      const float value = glm::dot(direction, hull.vertices[next]);
      if (value > best) {
        best = value;
        at = next;
        moved = true;
      }
    }
  }
  start = at;
  return best;
}

// The largest value of dot(direction, v) over every hull vertex: the proof the ascent's answer
// needs (Qhull's facet graph after its merges can leave the ascent on a vertex that is not the
// maximum: the vase's outer wall had a vertex 14 mm in front of a plane the ascent accepted).
float farthestOfAll(const Hull& hull, const vec3& direction) {
  float best = -INFINITY;
  for (const vec3& v : hull.vertices) best = std::max(best, glm::dot(direction, v));
  return best;
}

// Hull vertices times triangle sides to prove beyond which no side is proved (all of them count as
// not supporting: a mirror ray is cast there), so that a huge convex relic's load stays bounded.
constexpr double kProofBudget = 4e8;

}  // namespace

SupportingPlanes findSupportingPlanes(const Model& relic) {
  SupportingPlanes planes;
  planes.sides.resize(relic.meshes.size());
  std::vector<double> points;
  for (const TriangleMesh& mesh : relic.meshes)
    if (!mesh.triangles.empty())
      for (const vec3& p : mesh.positions)
        points.insert(points.end(), {double(p.x), double(p.y), double(p.z)});
  const Hull hull = convexHull(points);
  planes.hull_vertices = hull.vertices.size();
  for (std::size_t m = 0; m < relic.meshes.size(); ++m)
    planes.sides[m].assign(relic.meshes[m].triangles.size(), 0);
  if (hull.vertices.empty()) {
    HOLO_LOG_DEBUG("relic hull: none (degenerate), every mirror ray is cast");
    return planes;
  }
  const Bounds3 bounds = relic.bounds();
  const float tolerance = kSupportTolerance * glm::length(bounds.hi - bounds.lo);
  std::size_t candidates = 0;
  for (std::size_t m = 0; m < relic.meshes.size(); ++m) candidates += 2 * relic.meshes[m].triangles.size();
  const bool prove = double(candidates) * double(hull.vertices.size()) <= kProofBudget;
  if (!prove) HOLO_LOG_DEBUG("relic hull: too large to prove supporting planes, every mirror ray is cast");
  for (std::size_t m = 0; m < relic.meshes.size() && prove; ++m) {
    const TriangleMesh& mesh = relic.meshes[m];
    std::vector<std::uint8_t>& sides = planes.sides[m];
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::uint32_t front_start = 0, back_start = 0;
                        for (std::size_t t = range.begin(); t < range.end(); ++t) {
                          const uvec3& tri = mesh.triangles[t];
                          const vec3 &a = mesh.positions[tri.x], &b = mesh.positions[tri.y],
                                     &c = mesh.positions[tri.z];
                          const vec3 cross = glm::cross(b - a, c - a);
                          const float length = glm::length(cross);
                          if (!(length > 0.0f)) continue;
                          const vec3 n = cross / length;
                          const float plane = glm::dot(n, a);
                          std::uint8_t bits = 0;
                          // The ascent rejects most sides at once (its value is a vertex's);
                          // a side it accepts is proved over every hull vertex.
                          if (farthestAlong(hull, n, front_start) - plane <= tolerance &&
                              farthestOfAll(hull, n) - plane <= tolerance)
                            bits |= kFrontSupporting;
                          if (farthestAlong(hull, -n, back_start) + plane <= tolerance &&
                              farthestOfAll(hull, -n) + plane <= tolerance)
                            bits |= kBackSupporting;
                          sides[t] = bits;
                        }
                      });
  }
  return planes;
}

}  // namespace holo::reflect
