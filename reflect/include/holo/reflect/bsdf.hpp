// Surface scattering of the relic: glTF 2.0 metallic-roughness as the glTF specification's
// reference BRDF defines it (appendix B): GGX microfacets with Smith height-correlated masking,
// Schlick Fresnel, Lambert diffuse, mixed by metallic. The dielectric Fresnel is
// KHR_materials_specular's with KHR_materials_ior's F0 (the extension's fresnel_mix):
// F = specular (f0 + (1 - f0) (1 - v.h)^5), f0 = dielectricF0(ior, specular_colour) (0.04 for the
// glTF defaults; specular 0 = a pure Lambert surface); the diffuse gets 1 - max over RGB of F.
//
// Conventions: every direction is a unit world vector pointing AWAY from the surface (wo to the
// viewer, wi to the light); `normal` is the unit shading normal on the viewer's side.
// eval() returns f(wo, wi) * cos(theta_i) (so a sample's weight is eval / pdf); pdfs are per
// unit solid angle. Directions below the shading hemisphere scatter nothing (finite zero).
// Roughness below kDeltaRoughness is an exact mirror: a delta lobe that eval() and pdf() never
// see and sample() returns with `delta` set, so no tiny-lobe blows up.
#pragma once

#include <optional>

#include "holo/core/math.hpp"

namespace holo::reflect {

inline constexpr float kDeltaRoughness = 0.01f;  // perceptual roughness; alpha = roughness^2
inline constexpr float kDielectricF0 = 0.04f;    // glTF default (IOR 1.5); the clearcoat's F0

struct SurfaceMaterial {
  vec3 base_colour{0.8f};  // linear RGB albedo (dielectric) or F0 (metal), [0,1]
  float metallic = 0.0f;   // [0,1]
  float roughness = 1.0f;  // [0,1] perceptual; GGX alpha = roughness^2
  float specular = 1.0f;   // [0,1] dielectric Fresnel scale (KHR_materials_specular)
  // specular_colour and ior set every dielectric's F0 (dielectricF0); the rest is read by the
  // ground truth's MaterialBsdf (dielectric.hpp) only, Bsdf below ignores it.
  vec3 specular_colour{1.0f};          // >= 0, scales the dielectric's F0 (KHR_materials_specular)
  float transmission = 0.0f;           // [0,1] (KHR_materials_transmission)
  float ior = 1.5f;                    // >= 1 (KHR_materials_ior)
  bool thin_walled = true;             // KHR_materials_volume thickness 0 (or no volume)
  vec3 attenuation_colour{1.0f};       // [0,1] after attenuation_distance in the volume
  float attenuation_distance = 1e30f;  // metres, > 0; huge: clear
  float clearcoat = 0.0f;              // [0,1] layer weight (KHR_materials_clearcoat)
  float clearcoat_roughness = 0.0f;    // [0,1] perceptual
};

// The opaque dielectric's reflectance at normal incidence before the specular factor, per RGB
// channel in [0,1]: min(((ior - 1) / (ior + 1))^2 specular_colour, 1) (KHR_materials_specular
// with KHR_materials_ior). Computed in double, so the defaults (IOR 1.5, colour 1) give exactly
// kDielectricF0. An IOR below 1 counts as 1 (F0 0), +infinity as a perfect mirror (1), NaN as
// 1.5; a negative or NaN colour channel as 0. Shared by the path tracer's Bsdf, the split-sum
// shading (PrefilteredIbl::shadeParts) and the live refraction pass.
vec3 dielectricF0(float ior, const vec3& specular_colour);

// GGX building blocks in a local frame where the normal is +Z (exposed for the prefilter, the
// DFG table and tests). alpha > 0.
namespace ggx {
float D(float cos_theta_h, float alpha);          // normal distribution, 1/sr
float lambda(float cos_theta, float alpha);       // Smith Lambda
float G1(float cos_theta, float alpha);           // Smith masking
float G2(float cos_o, float cos_i, float alpha);  // height-correlated masking-shadowing
// Heitz 2018 visible-normal sample for view `wo_local` (z > 0); u in [0,1)^2.
vec3 sampleVisibleNormal(const vec3& wo_local, float alpha, const vec2& u);
// Normal-distribution sample (pdf of h = D(h) cos_theta_h); used by the prefilter.
vec3 sampleNormal(float alpha, const vec2& u);
}  // namespace ggx

vec3 schlickFresnel(const vec3& f0, float cos_theta);
float roughnessToAlpha(float roughness);

// Orthonormal frame around a unit normal (Duff et al. 2017, no branch on a seam).
struct Frame {
  vec3 t, b, n;
  explicit Frame(const vec3& normal);
  vec3 toLocal(const vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
  vec3 toWorld(const vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

struct BsdfSample {
  vec3 wi{0.0f};      // world, unit
  vec3 weight{0.0f};  // f * cos / pdf (for delta: the reflectance / lobe probability)
  float pdf = 0.0f;   // solid-angle pdf of the whole mixture (0 for a delta sample)
  bool delta = false;
  bool transmitted = false;  // wi is behind the surface (dielectric.hpp's transmission)
  bool dielectric = false;   // scattered by dielectric.hpp's glass lobe (reflected or refracted)
};

class Bsdf {
 public:
  Bsdf(const SurfaceMaterial& material, const vec3& normal);

  vec3 eval(const vec3& wo, const vec3& wi) const;  // f * cos(theta_i), non-delta lobes
  float pdf(const vec3& wo, const vec3& wi) const;  // pdf of sample() over non-delta lobes
  // u in [0,1)^3: u.x picks the lobe, u.yz the direction. nullopt when nothing scatters.
  std::optional<BsdfSample> sample(const vec3& wo, const vec3& u) const;

  bool mirror() const { return delta_; }
  bool hasDiffuse() const;
  const SurfaceMaterial& material() const { return m_; }
  const vec3& normal() const { return frame_.n; }

 private:
  float specularProbability(float cos_o) const;
  vec3 evalLocal(const vec3& wo, const vec3& wi) const;
  float pdfLocal(const vec3& wo, const vec3& wi, float p_spec) const;
  vec3 dielectricFresnel(float cos_vh) const;  // specular x Schlick(f0_), RGB
  vec3 specularFresnel(float cos_vh) const;    // the whole specular lobe's, metal mixed in
  SurfaceMaterial m_;
  vec3 f0_;  // dielectricF0 of m_
  Frame frame_;
  float alpha_;
  bool delta_;
};

}  // namespace holo::reflect
