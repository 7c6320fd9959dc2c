// The foreground point cloud: what the depth filter hands to the reflection stage every frame.
// Every point is a filtered foreground pixel of one camera, back-projected into the world
// (pyramid) frame, and keeps its source (camera, pixel) so the reflection tracer can look the
// pixel up in that camera's blurred colour pyramids. Units: metres, linear radiance.
#pragma once

#include <cstdint>
#include <vector>

#include "holo/core/math.hpp"

namespace holo::depthfilter {

struct ForegroundPoint {
  vec3 position{0.0f};  // world frame, metres
  vec3 radiance{0.0f};  // linear RGB: the camera's sRGB colour linearised and divided by exposure
  float weight = 1.0f;  // mask value phi in (0, 1]; below 1 on the expanded border
  std::uint16_t camera = 0;
  std::uint16_t x = 0;  // source pixel column
  std::uint16_t y = 0;  // source pixel row
};

// Invariant: every position and radiance is finite; weights lie in (0, 1].
struct ForegroundCloud {
  std::vector<ForegroundPoint> points;
  std::int64_t sequence = -1;  // frame the cloud was built from; -1 before the first frame
  double time_s = 0.0;         // capture time of that frame (host clock, seconds)

  bool empty() const { return points.empty(); }
  Bounds3 bounds() const {
    Bounds3 b;
    for (const ForegroundPoint& p : points) b.extend(p.position);
    return b;
  }
};

}  // namespace holo::depthfilter
