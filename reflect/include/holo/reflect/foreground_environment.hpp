// The paper's IBL baseline environment: the dynamic foreground (a world-space point cloud with
// linear colours, as the depth filter produces it) reprojected into an equirectangular map
// centred on the relic and merged over the static panorama, which is then prefiltered
// (prefiltered_ibl.hpp) and used for every reflection. Nearer points win (a depth test per
// pixel); each point is splatted as a disc of its own physical size (point_radius metres) seen
// from the centre, so a surface sampled every ~1 cm is closed without holes. Directions use
// core/equirect.hpp (with the static panorama's yaw).
#pragma once

#include <vector>

#include "holo/core/math.hpp"
#include "holo/reflect/environment.hpp"

namespace holo::reflect {

struct ForegroundPoints {
  std::vector<vec3> positions;  // world, metres
  std::vector<vec3> colors;     // linear RGB radiance, one per position
};

struct ReprojectionStats {
  long points_used = 0;
  long points_rejected = 0;  // non-finite, at the centre, or without a colour
  long pixels_covered = 0;
};

// A copy of `static_panorama` (CV_32FC3 BGR) with the foreground drawn over it as seen from
// `centre`.
cv::Mat mergeForeground(const cv::Mat& static_panorama, const ForegroundPoints& points,
                        const vec3& centre, float point_radius = 0.01f, float yaw = 0.0f,
                        ReprojectionStats* stats = nullptr);

}  // namespace holo::reflect
