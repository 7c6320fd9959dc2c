// Mesh primitives the built-in relics and the simulated halls and visitors are built from. Every builder
// returns a closed (or, for lathes, optionally open) triangle mesh with per-vertex unit normals
// in its own local frame, in metres; place it with TriangleMesh::transform or appendMesh.
#pragma once

#include <vector>

#include "holo/core/mesh.hpp"

namespace holo {

// Axis-aligned box centred at the origin with the given half extents (flat-shaded faces).
TriangleMesh makeBox(const vec3& half_extent);
// Cylinder along +Y from y = 0 to y = height, capped at both ends.
TriangleMesh makeCylinder(float radius, float height, int segments = 24);
// UV sphere centred at the origin.
TriangleMesh makeSphere(float radius, int rings = 12, int segments = 24);
// Surface of revolution about +Y of a profile of (radius, y) points, bottom to top; uvs are
// (angle / 2 pi, profile parameter). Points with radius 0 close the surface there.
TriangleMesh makeLathe(const std::vector<vec2>& profile, int segments = 48);
// A tube of circular cross-section along a polyline (at least 2 points), one radius per point.
TriangleMesh makeTube(const std::vector<vec3>& path, const std::vector<float>& radii, int segments = 16);

// One cross-section of an elliptic sweep: an ellipse in the plane y, centred at (0, y, centre_z),
// with half extents half_x along X and half_z along Z (metres). A ring with both half extents 0
// is a point, which closes the surface there.
struct EllipseRing {
  float y = 0.0f;
  float half_x = 0.0f;
  float half_z = 0.0f;
  float centre_z = 0.0f;
};
// Surface through elliptic rings, bottom to top (y need not increase), `segments` vertices per
// ring; closed when the first and last rings are points. Smooth area-weighted normals; uvs are
// (angle / 2 pi, ring index / (rings - 1)).
TriangleMesh makeEllipticSweep(const std::vector<EllipseRing>& rings, int segments = 16);

// Appends `part`, transformed by T, to `dst` (keeps dst's material).
void appendMesh(TriangleMesh& dst, const TriangleMesh& part, const mat4& T = mat4(1.0f));

// Catmull-Rom resampling of a smooth profile through control points (samples per segment).
std::vector<vec2> smoothProfile(const std::vector<vec2>& control, int samples_per_segment = 8);

}  // namespace holo
