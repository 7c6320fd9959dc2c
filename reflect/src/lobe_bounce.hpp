// The rough lobe's interreflection samples (internal), shared by the static shading that traces
// them (static_shading.hpp) and the axis-aligned filter that smooths them (axis_aligned_filter.hpp).
// Counts are of rays, light is linear radiance, distances metres.
#pragma once

#include <algorithm>
#include <limits>

#include "holo/core/math.hpp"

namespace holo::reflect {

// The rough lobe's interreflection samples of one hit point (or their weighted sum over pixels).
struct LobeBounce {
  float above = 0.0f, met = 0.0f;      // lobe samples above the surface; those that met the relic
  vec3 diffuse{0.0f}, specular{0.0f};  // sums over the met ones of their second points' shading
  // Metres to the nearest second point (axis_aligned_filter.hpp's z_min); infinite: none met.
  float nearest = std::numeric_limits<float>::infinity();
  // Adds `other`'s sums times `weight` (>= 0); a positive weight brings its nearest point along.
  void add(const LobeBounce& other, float weight) {
    above += weight * other.above;
    met += weight * other.met;
    diffuse += weight * other.diffuse;
    specular += weight * other.specular;
    if (weight > 0.0f) nearest = std::min(nearest, other.nearest);
  }
};

// A pixel's interleaved lobe samples and where they lie (its first rough sample's point).
struct PixelBounce {
  bool rough = false;
  vec3 position{0.0f}, normal{0.0f};
  float roughness = 0.0f;  // of the first rough sample's material
  LobeBounce samples;
};

}  // namespace holo::reflect
