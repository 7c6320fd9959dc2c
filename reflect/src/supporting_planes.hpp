// Which of the relic's triangles lie in a supporting plane of the relic: the whole relic (every
// vertex of every mesh) behind the triangle's plane on one of its sides, up to a tolerance of
// kSupportTolerance times the relic's bounding-box diagonal. A ray leaving such a triangle to
// that side cannot meet the relic again, so the interreflection's mirror ray need not be cast
// there: on a convex relic no triangle casts one. Conservative: a triangle is flagged only when
// the test proves it; a relic whose hull cannot be built (fewer than four points off one plane)
// flags none.
#pragma once

#include <cstdint>
#include <vector>

#include "holo/core/mesh.hpp"

namespace holo::reflect {

inline constexpr float kSupportTolerance = 1e-5f;

// Bits per triangle: the relic lies behind the triangle's plane on its front side (the side its
// winding's normal cross(p1 - p0, p2 - p0) points to) or on its back side.
enum SupportingSide : std::uint8_t { kFrontSupporting = 1, kBackSupporting = 2 };

// sides[m][t]: the SupportingSide bits of triangle t of relic.meshes[m].
struct SupportingPlanes {
  std::vector<std::vector<std::uint8_t>> sides;
  std::size_t hull_vertices = 0;  // of the relic's convex hull (0: none could be built)
};

// Builds the relic's convex hull (Qhull) and tests every triangle's plane against it: an ascent
// over the hull's facet graph rejects most sides at once, and a side it accepts is proved against
// every hull vertex (the graph Qhull leaves after merging facets can stop the ascent short of the
// maximum). Where hull vertices times triangle sides exceed 4e8 no side is flagged (a bounded load).
SupportingPlanes findSupportingPlanes(const Model& relic);

}  // namespace holo::reflect
