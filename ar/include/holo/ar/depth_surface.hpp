// The real surfaces near the relic as one camera's depth sees them: a triangle mesh in the world
// frame with a vertex per valid depth pixel within `radius` of `centre`, two triangles per 2x2
// block of such pixels whose depths stay within `max_depth_step` of each other (relative: a jump
// between a near and a far surface is a silhouette, not a surface), area-weighted normals.
// Units: metres; depth CV_32FC1 camera-frame z, 0 = invalid.
#pragma once

#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/core/image.hpp"
#include "holo/core/mesh.hpp"

namespace holo::ar {

struct DepthSurfaceSettings {
  vec3 centre{0.0f};             // the local scene's centre (the relic's place), world
  float radius = 1.5f;           // metres: farther points are the panorama's
  float max_depth_step = 0.05f;  // largest depth ratio - 1 between connected neighbours
};

struct DepthSurface {
  TriangleMesh mesh;          // world frame, normals per vertex
  std::vector<ivec2> pixels;  // per vertex, the depth pixel it came from
};

// Throws InputError naming `camera_name` when the depth is not CV_32FC1 of the camera's size.
DepthSurface depthSurface(const cv::Mat& depth, const CameraModel& camera,
                          const DepthSurfaceSettings& settings, const std::string& camera_name);

}  // namespace holo::ar
