#include "clearcoat.hpp"

#include <algorithm>
#include <cmath>

#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/dfg_table.hpp"
#include "layer_inputs.hpp"

namespace holo::reflect {

ClearcoatLayer shadeClearcoat(const PrefilteredIbl& ibl, const HitPoint& hp) {
  // The coat's weight and roughness as the hit point sampled them, around its own normal.
  const float weight = clamp01(hp.material.clearcoat);
  const float roughness = clamp01(hp.material.clearcoat_roughness);
  const float coat_nv = std::clamp(glm::dot(hp.clearcoat_normal, hp.to_viewer), 1e-4f, 1.0f);
  const vec2 ab = dfg(coat_nv, roughness);
  ClearcoatLayer coat;
  coat.scale = vec3(weight * (kDielectricF0 * ab.x + ab.y));
  coat.environment =
      iblSeenFrom(ibl, hp.position, glm::reflect(-hp.to_viewer, hp.clearcoat_normal), roughness);
  const float schlick = kDielectricF0 + (1.0f - kDielectricF0) * std::pow(1.0f - coat_nv, 5.0f);
  coat.below = 1.0f - weight * schlick;
  return coat;
}

}  // namespace holo::reflect
