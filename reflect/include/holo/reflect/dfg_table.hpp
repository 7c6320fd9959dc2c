// The split-sum "DFG" table (Karis 2013): the directional albedo of the GGX specular lobe with
// Smith height-correlated masking, split by Schlick Fresnel into a scale and a bias, so that
//   integral f_spec(wo, wi) cos(theta_i) dwi = F0 * A + F90 * B,  (A, B) = dfg(n.v, roughness).
// Tabulated once per process (32 x 32, 1024 Hammersley visible-normal samples per cell) and
// interpolated bilinearly; roughness below kDeltaRoughness is the exact mirror (A = 1 - s, B = s
// with s = (1 - n.v)^5).
#pragma once

#include "holo/core/math.hpp"

namespace holo::reflect {

vec2 dfg(float n_dot_v, float roughness);
// The same quantity computed directly (no table), for tests and the table itself.
vec2 dfgIntegrate(float n_dot_v, float roughness, int samples);

}  // namespace holo::reflect
