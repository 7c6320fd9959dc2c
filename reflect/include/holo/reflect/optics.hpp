// The optics of a smooth dielectric interface and of an absorbing volume, shared by the live
// refraction pass (reflect/src/glass_transport.cpp) and the ground truth's glass BSDF
// (dielectric.hpp): Snell's law, the exact unpolarised Fresnel reflectance and Beer-Lambert
// absorption (KHR_materials_transmission, _ior, _volume).
//
// Conventions: eta = n_t / n_i, the IOR on the far side of the interface over the IOR on the side
// the light arrives from (> 0; 1 is an invisible interface); directions are unit vectors;
// absorption coefficients are per metre and per RGB channel.
#pragma once

#include <optional>

#include "holo/core/math.hpp"

namespace holo::reflect {

// Exact unpolarised Fresnel reflectance of a smooth dielectric interface for light arriving at
// cos_i (> 0) from the side of IOR n_1, eta = n_2 / n_1 > 0. 1 beyond the critical angle (total
// internal reflection); a NaN cosine counts as grazing, a NaN or non-positive eta as 1.
float fresnelDielectric(float cos_i, float eta);

// Snell's law: sin^2 of the transmitted angle for light arriving at cos_i, (1 - cos_i^2) / eta^2
// with cos_i clamped to [0, 1]; at least 1 beyond the critical angle (total internal reflection).
float refractedSin2(float cos_i, float eta);

// Snell refraction of the incident direction `d` (travelling towards the interface) through the
// unit normal `n` on its side: d / eta + (cos_i / eta - cos_t) n, cos_t = sqrt(max(0, 1 -
// refractedSin2(cos_i, eta))), so beyond the critical angle the grazing direction. cos_i is -d.n as
// the caller measured it. Unit up to rounding and not renormalised: each caller renormalises as
// its own arithmetic has it (refractDirection, refractIncident).
vec3 snellRefraction(const vec3& d, const vec3& n, float eta, float cos_i);

// The path tracer's convention: the direction refracted from `wo` (pointing away from the surface,
// on the side the unit normal `h` points to, wo.h > 0), renormalised; nullopt on total internal
// reflection.
std::optional<vec3> refractDirection(const vec3& wo, const vec3& h, float eta);

// The live pass's convention: the direction refracted from the incident `d` (towards the surface,
// against the unit normal `n`), cos_i = -d.n clamped to [0, 1]; the caller has checked that it is
// not totally reflected. Renormalised by its length; `d` itself where that length vanishes.
vec3 refractIncident(const vec3& d, const vec3& n, float eta);

// Beer-Lambert absorption coefficient sigma (1/m, per RGB channel) of KHR_materials_volume: white
// light has `colour` (clamped to [0, 1]) after `distance` metres, sigma = -ln(colour) / distance.
// 0 for a clear volume (an infinite, NaN or non-positive distance). A channel of colour 0 (or NaN)
// is fully absorbed after any distance > 0: its sigma is kOpaqueAbsorption, finite so that
// transmittance over a distance of 0 stays 1 rather than NaN; every sigma is capped there.
inline constexpr float kOpaqueAbsorption = 1e30f;
vec3 attenuationCoefficient(const vec3& colour, float distance);

// The share of light left after `distance` metres through a volume of coefficient sigma:
// exp(-sigma distance) per channel.
vec3 transmittance(const vec3& sigma, float distance);

}  // namespace holo::reflect
