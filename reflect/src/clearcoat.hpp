// The clearcoat (internal): KHR_materials_clearcoat's second specular lobe on top of a hit point's
// static shading (and its transmitted light), for the refraction pass (refraction_pass.hpp).
//
// A smooth-to-rough dielectric layer of IOR 1.5: coat = clearcoat x (split-sum 0.04 A + B of its
// roughness), reading the IBL at the clearcoat roughness along the mirror of the coat's own normal
// (its normal map's, else the base's) and the base's walked foreground; the base below
// (reflection, diffuse, transmission) is scaled by 1 - clearcoat x Schlick(0.04, n.v) of the coat's
// normal. Weight and roughness are the factors times their textures as the hit point sampled them.
#pragma once

#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"

namespace holo::reflect {

struct ClearcoatLayer {
  vec3 scale{0.0f};        // the coat's split-sum weight of what its mirror direction sees
  vec3 environment{0.0f};  // the prefiltered IBL along that direction at the coat's roughness
  float below = 1.0f;      // the factor of the base under the coat
};

// The coat of hit point `hp` (its material's clearcoat > 0).
ClearcoatLayer shadeClearcoat(const PrefilteredIbl& ibl, const HitPoint& hp);

}  // namespace holo::reflect
