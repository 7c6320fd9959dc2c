// What sampling the rough lobe's interreflection can leave on the display (internal): the bound
// the effect plan weighs the axis-aligned filter and progressive refinement with, the two passes
// that change only how the lobe's strata are sampled and pooled (static_shading.hpp), not what
// they converge to. A pixel's lobe term is specular_scale (<= 1) times two sampled parts, the
// hall seen through the open strata and the relic's own light through the strata that meet it,
// each a mean over the pixel's N pooled strata (N = rough_interreflection_grid^2: the 3x3 tent
// gives the 2x2 pixel classes' strata equal weight) of light within [0, R]: the hall at most the
// IBL's brightest(), a second point of the relic reflecting no more than that and emitting at
// most the relic's largest emission. A mean of N stratified samples within [0, R] has a standard
// deviation of at most R / (2 sqrt(N)), the two parts' sum at most R / sqrt(N); the spread is twice
// that, 2 R / sqrt(N): what the filter can take out of a pixel and the accumulated sets can move
// it by, in linear radiance.
#pragma once

#include <algorithm>

#include "holo/core/math.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reflect {

inline float lobeSpread(const RenderScene& scene, const PrefilteredIbl& ibl, int strata_grid) {
  float emission = 0.0f;
  for (const Material& m : scene.relic().materials) emission = std::max(emission, maxComponent(m.emission));
  const float reach = maxComponent(ibl.brightest()) + emission;
  return 2.0f * reach / float(std::max(strata_grid, 1));
}

}  // namespace holo::reflect
