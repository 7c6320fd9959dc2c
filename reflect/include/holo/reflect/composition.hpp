// Step 5 of the paper: psi_f = psi_d * w + psi_s * (1 - w), in linear HDR. Here psi_d and psi_s are
// the specular (reflected) radiances of the foreground and of the static environment at the same
// hit point and w the foreground weight; the diffuse part, the same for both, is added by the
// caller. Bounded for any input: w is clamped to [0, 1] (a non-finite w -> 0: no foreground); a
// non-finite or negative channel of psi_d or psi_s counts as 0, so the output is always finite
// and >= 0.
#pragma once

#include "holo/core/math.hpp"

namespace holo::reflect {

vec3 composeReflection(const vec3& psi_d, const vec3& psi_s, float w);

}  // namespace holo::reflect
