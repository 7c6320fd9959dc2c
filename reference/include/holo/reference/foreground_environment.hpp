// Evaluation only: a reference for measuring the appliance's renderer, never linked by it
// (reference/CMakeLists.txt).
// The paper's IBL baseline environment: the dynamic foreground (the depth filter's world-space
// point cloud, holo::depthfilter::ForegroundCloud, linear radiance) reprojected into an equirectangular map
// centred on the relic and merged over the static panorama, which is then prefiltered
// (prefiltered_ibl.hpp) and used for every reflection. Nearer points win (a depth test per
// pixel); each point is splatted as a disc of its own physical size (point_radius metres) seen
// from the centre, so a surface sampled every ~1 cm is closed without holes. Directions use
// core/equirect.hpp (with the static panorama's yaw). A point's mask weight phi blends its
// radiance over the static panorama (phi < 1 on the expanded mask border), as the tracer does.
#pragma once

#include <vector>

#include "holo/core/math.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/reflect/environment.hpp"

namespace holo::reference {

struct ReprojectionStats {
  long points_used = 0;
  long points_rejected = 0;  // non-finite, at the centre, or with weight <= 0
  long pixels_covered = 0;
};

// A copy of `static_panorama` (CV_32FC3 BGR) with the foreground drawn over it as seen from
// `centre`.
cv::Mat mergeForeground(const cv::Mat& static_panorama, const depthfilter::ForegroundCloud& cloud,
                        const vec3& centre, float point_radius = 0.01f, float yaw = 0.0f,
                        ReprojectionStats* stats = nullptr);

}  // namespace holo::reference
