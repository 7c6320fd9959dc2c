// The rough lobe's interreflection samples (internal), shared by the static shading that traces
// them (static_shading.hpp) and the axis-aligned filter that smooths them (axis_aligned_filter.hpp).
// Counts are of rays, light is linear radiance, distances metres.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "holo/core/math.hpp"

namespace holo::reflect {

// The rough lobe's interreflection samples of one hit point (or their weighted sum over pixels).
struct LobeBounce {
  float above = 0.0f, met = 0.0f;      // lobe samples above the surface; those that met the relic
  vec3 diffuse{0.0f}, specular{0.0f};  // sums over the met ones of their second points' shading
  // The hall's prefiltered radiance along each sample, read at its stratum's share of the lobe
  // (filtered importance sampling): summed over the samples above, and over those that missed.
  vec3 hall{0.0f}, open{0.0f};
  // Metres to the nearest second point (axis_aligned_filter.hpp's z_min); infinite: none met.
  float nearest = std::numeric_limits<float>::infinity();
  // Adds `other`'s sums times `weight` (>= 0); a positive weight brings its nearest point along.
  void add(const LobeBounce& other, float weight) {
    above += weight * other.above;
    met += weight * other.met;
    diffuse += weight * other.diffuse;
    specular += weight * other.specular;
    hall += weight * other.hall;
    open += weight * other.open;
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

// A view's pixels' lobe samples, kept from one static pass to the next. `pixels` is sized to the
// view and default everywhere but at `rough`, the pixels the last pass marked rough (in no
// particular order), so that a pass resets those alone instead of every pixel of the view.
struct ViewBounces {
  std::vector<PixelBounce> pixels;
  std::vector<std::uint32_t> rough;
};

}  // namespace holo::reflect
