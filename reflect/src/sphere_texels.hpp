// The texels of an equirectangular map over the whole sphere (internal): the unit direction
// through each texel's centre and its solid angle (steradians), row-major, x fastest. The maps
// that splat the visitors around the relic (rough_foreground_map.hpp, visitor_light.hpp) read them.
#pragma once

#include <cstddef>
#include <vector>

#include "holo/core/equirect.hpp"
#include "holo/core/math.hpp"

namespace holo::reflect {

struct SphereTexels {
  std::vector<vec3> direction;
  std::vector<float> solid_angle;
};

inline SphereTexels sphereTexels(int width, int height) {
  SphereTexels out;
  const std::size_t n = std::size_t(width) * std::size_t(height);
  out.direction.resize(n);
  out.solid_angle.resize(n);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t t = std::size_t(y) * std::size_t(width) + std::size_t(x);
      out.direction[t] =
          equirect::uvToDirection({(float(x) + 0.5f) / float(width), (float(y) + 0.5f) / float(height)});
      out.solid_angle[t] = equirect::pixelSolidAngle(y, width, height);
    }
  return out;
}

}  // namespace holo::reflect
