// How the frame renderer's material layers (glass_transport.hpp, refraction_pass.hpp,
// clearcoat.hpp) read a glTF factor, an IOR and the hall's prefiltered IBL (internal).
#pragma once

#include <algorithm>
#include <cmath>

#include "holo/core/math.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"

namespace holo::reflect {

// A glTF factor in [0, 1]; a NaN or infinite one reads as 0.
inline float clamp01(float v) {
  return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
}

// An IOR as the glass reads it: below 1, NaN or infinite reads as 1 (no interface).
inline float safeIor(float ior) {
  return std::isfinite(ior) && ior >= 1.0f ? ior : 1.0f;
}

// The prefiltered IBL a ray from `origin` along `direction` reads at perceptual `roughness`:
// through the panorama's proxy, so the hall's parallax is the same as the static shading's.
inline vec3 iblSeenFrom(const PrefilteredIbl& ibl, const vec3& origin, const vec3& direction,
                        float roughness) {
  return ibl.seenFrom(origin, direction, roughness);
}

}  // namespace holo::reflect
