// What another view says about a point of one camera's image: whether a surface is seen there,
// whether the space there is seen through (empty), or nothing (out of view, hidden, unread).
// The temporal depth filter asks this of a hole's candidate surfaces where its own neighbours
// span two surfaces of one colour (temporal_depth_filter.hpp); OtherCameraWitness answers it
// from the other cameras' measured depth.
//
// Units: pixels of the asking camera's image, depth = camera-frame z in metres.
#pragma once

#include <cstdint>

namespace holo::depthfilter {

enum class Sighting : std::uint8_t {
  Unknown = 0,  // no view measured anything that decides
  Seen,         // a view measured a visitor's surface at the point
  Empty,        // a view measured a surface beyond the point: the space there is empty
};

class SurfaceWitness {
 public:
  virtual ~SurfaceWitness() = default;
  // The point of pixel (x, y) at camera-frame depth `depth` (> 0).
  virtual Sighting sighting(int x, int y, float depth) const = 0;
};

}  // namespace holo::depthfilter
