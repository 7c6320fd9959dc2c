// Scattering by glass and by every glTF 2.0 material the path tracer renders (evaluation only:
// the ground truth's BSDF; the live renderer keeps bsdf.hpp's opaque lobes).
//
// DielectricBsdf: the transmissive dielectric of KHR_materials_transmission - exact unpolarised
// Fresnel, Snell refraction with total internal reflection and Beer-Lambert absorption (optics.hpp,
// shared with the live refraction pass), GGX rough reflection and transmission (Walter et al.
// 2007, sampled with bsdf.hpp's visible normals), and the thin-walled variant (transmission
// without KHR_materials_volume: straight through, no bending; a rough wall blurs
// around the straight-through direction). KHR_materials_specular's factors act on its Fresnel:
// F = specular (f0' + (1 - f0') g) with f0' = min(f0 specular_colour, 1) and g = (F_exact - f0) /
// (1 - f0) the exact Fresnel's own rise to grazing, so the factors 1 give the exact Fresnel;
// transmission gets 1 - max(F) (the glTF fresnel_mix), tinted by base_colour on entering.
//
// MaterialBsdf: the glTF BSDF as its specification composes it:
//   material = mix(dielectric_brdf, metal_brdf, metallic), dielectric_brdf = fresnel_mix(specular,
//   base = mix(diffuse, btdf, transmission)),
// written as (1 - w) Bsdf(metallic / (1 - w)) + w DielectricBsdf with w = (1 - metallic)
// transmission, under KHR_materials_clearcoat's layer: clearcoat F_cc(v.h) f_ggx(cc roughness) +
// (1 - clearcoat F_cc(n.v)) base, F_cc Schlick with f0 0.04 (IOR 1.5), as the extension says.
// Seen from inside a volume (a back face of a transmissive material with thickness > 0) only the
// dielectric interface scatters, with the IORs swapped.
//
// Radiance, not importance: the path tracer gathers radiance from the camera, so a refraction
// from the wo side (IOR n_o) to the wi side (IOR n_i) carries (n_o / n_i)^2 (radiance is
// compressed entering glass, expanded leaving it; a path that leaves into the medium it came from
// gets both factors and they cancel). eval() therefore obeys the generalised reciprocity
// f(wo, wi) / n_o^2 = f(wi, wo) / n_i^2, and the flux it scatters (f integrated over wo for a
// fixed wi, cosine-weighted) is at most 1.
//
// Conventions as bsdf.hpp: unit world directions pointing away from the surface; `normal` is the
// unit shading normal on wo's side; eval() returns f(wo, wi) |cos theta_i| for wi on either side;
// pdfs per unit solid angle; delta lobes (roughness below kDeltaRoughness) only in sample().
#pragma once

#include <optional>

#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/optics.hpp"

namespace holo::reference {

class DielectricBsdf {
 public:
  // `eta` = IOR on the far side of `normal` / IOR on its side (> 0; 1 is an invisible interface).
  // `tint` multiplies transmitted light (base_colour on entering, 1 leaving).
  DielectricBsdf(const reflect::SurfaceMaterial& material, const vec3& normal, float eta, const vec3& tint,
                 bool thin_walled);

  vec3 eval(const vec3& wo, const vec3& wi) const;
  float pdf(const vec3& wo, const vec3& wi) const;
  std::optional<reflect::BsdfSample> sample(const vec3& wo, const vec3& u) const;
  bool delta() const { return delta_; }

 private:
  // Reflectance (RGB, KHR_materials_specular applied) at cos(wo, h); 1 on total internal reflection.
  vec3 fresnel(float cos_oh) const;
  vec3 evalLocal(const vec3& wo, const vec3& wi) const;
  float pdfLocal(const vec3& wo, const vec3& wi) const;
  reflect::Frame frame_;
  float alpha_;
  float eta_;
  float f0_;        // exact normal-incidence reflectance ((eta - 1) / (eta + 1))^2
  vec3 f0_scaled_;  // min(f0 specular_colour, 1)
  float specular_;  // KHR_materials_specular weight
  vec3 tint_;
  bool thin_;
  bool delta_;
};

class MaterialBsdf {
 public:
  // `front`: wo is on the side the surface's glTF winding faces (outside a volume).
  // `clearcoat_normal`: the layer's own shading normal on wo's side (the base normal if none).
  MaterialBsdf(const reflect::SurfaceMaterial& material, const vec3& normal, bool front,
               const vec3& clearcoat_normal);
  MaterialBsdf(const reflect::SurfaceMaterial& material, const vec3& normal, bool front)
      : MaterialBsdf(material, normal, front, normal) {}

  vec3 eval(const vec3& wo, const vec3& wi) const;
  float pdf(const vec3& wo, const vec3& wi) const;
  // BsdfSample::transmitted says the path crossed the surface (into or out of a volume when the
  // material is not thin-walled); dielectric() says the glass lobe (reflection or refraction)
  // scattered it.
  std::optional<reflect::BsdfSample> sample(const vec3& wo, const vec3& u) const;
  bool hasNonDelta() const;
  bool thinWalled() const { return thin_; }

 private:
  // Selection probabilities of clearcoat, opaque base and dielectric at this wo.
  void lobeProbabilities(const vec3& wo, float p[3]) const;
  float baseScale(const vec3& wo) const;  // 1 - clearcoat F_cc(n_cc . wo)
  float transmissive_;                    // w = (1 - metallic) transmission; 1 inside a volume
  float clearcoat_;                       // 0 inside a volume
  bool thin_;
  reflect::Bsdf opaque_;
  reflect::Bsdf coat_;
  DielectricBsdf glass_;
};

}  // namespace holo::reference
