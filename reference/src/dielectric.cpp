#include "holo/reference/dielectric.hpp"

#include <algorithm>
#include <cmath>

#include "holo/reflect/optics.hpp"

namespace holo::reference {

using reflect::attenuationCoefficient;
using reflect::BsdfSample;
using reflect::fresnelDielectric;
using reflect::kDeltaRoughness;
using reflect::refractDirection;
using reflect::roughnessToAlpha;
using reflect::SurfaceMaterial;
namespace ggx = reflect::ggx;

namespace {

// Below this |eta - 1| the interface is index-matched: invisible, light passes straight through.
// (A rough interface with eta within 1e-3 of 1 bends rays by less than a thousandth of its lobe,
// and its half vector wo + eta wi cancels to rounding noise.)
constexpr float kIndexMatched = 1e-3f;
constexpr float kClearcoatF0 = 0.04f;  // KHR_materials_clearcoat: IOR 1.5

float schlickCoat(float cos_theta) {
  const float m = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
  const float m2 = m * m;
  return kClearcoatF0 + (1.0f - kClearcoatF0) * m2 * m2 * m;
}

SurfaceMaterial clearcoatLayer(const SurfaceMaterial& m) {
  // A metal of F0 0.04 is exactly the layer's Schlick-weighted GGX lobe.
  SurfaceMaterial layer;
  layer.base_colour = vec3(kClearcoatF0);
  layer.metallic = 1.0f;
  layer.roughness = m.clearcoat_roughness;
  return layer;
}

SurfaceMaterial opaqueBase(const SurfaceMaterial& m, float transmissive) {
  // (1 - w) Bsdf(metallic') must hold metallic of the whole: metallic' = metallic / (1 - w).
  SurfaceMaterial base = m;
  const float opaque = 1.0f - transmissive;
  base.metallic = opaque > 0.0f ? std::clamp(m.metallic / opaque, 0.0f, 1.0f) : 1.0f;
  return base;
}

bool finiteMaterial(const SurfaceMaterial& m) {
  return std::isfinite(m.ior) && std::isfinite(m.transmission) && std::isfinite(m.clearcoat) &&
         std::isfinite(m.clearcoat_roughness) && isFinite(m.specular_colour);
}

}  // namespace

DielectricBsdf::DielectricBsdf(const SurfaceMaterial& material, const vec3& normal, float eta,
                               const vec3& tint, bool thin_walled)
    : frame_(normal),
      alpha_(roughnessToAlpha(material.roughness)),
      eta_(std::isfinite(eta) && eta > 0.0f ? eta : 1.0f),
      tint_(glm::clamp(tint, vec3(0.0f), vec3(1.0f))),
      thin_(thin_walled) {
  const float r = (eta_ - 1.0f) / (eta_ + 1.0f);
  f0_ = r * r;
  specular_ = std::clamp(material.specular, 0.0f, 1.0f);
  f0_scaled_ = glm::min(f0_ * glm::max(material.specular_colour, vec3(0.0f)), vec3(1.0f));
  const bool index_matched = std::abs(eta_ - 1.0f) < kIndexMatched;
  if (index_matched) f0_ = 0.0f, f0_scaled_ = vec3(0.0f);
  delta_ = material.roughness < kDeltaRoughness || index_matched;
}

vec3 DielectricBsdf::fresnel(float cos_oh) const {
  if (f0_ <= 0.0f) return vec3(0.0f);
  const float exact = fresnelDielectric(cos_oh, eta_);
  if (exact >= 1.0f) return vec3(1.0f);  // total internal reflection: nothing is transmitted
  const float rise = std::clamp((exact - f0_) / (1.0f - f0_), 0.0f, 1.0f);
  return specular_ * (f0_scaled_ + (vec3(1.0f) - f0_scaled_) * rise);
}

vec3 DielectricBsdf::evalLocal(const vec3& wo, const vec3& wi) const {
  if (delta_ || wo.z <= 0.0f || wi.z == 0.0f) return vec3(0.0f);
  if (wi.z > 0.0f) {
    const vec3 h = glm::normalize(wo + wi);
    const vec3 f = fresnel(std::max(0.0f, glm::dot(wo, h)));
    return f * (ggx::D(h.z, alpha_) * ggx::G2(wo.z, wi.z, alpha_) / (4.0f * wo.z));
  }
  if (thin_) {
    // The wall's two interfaces shift the ray back: the lobe is the reflection lobe mirrored
    // through the surface, around the straight-through direction.
    const vec3 mirrored(wi.x, wi.y, -wi.z);
    const vec3 h = glm::normalize(wo + mirrored);
    const float transmitted = 1.0f - maxComponent(fresnel(std::max(0.0f, glm::dot(wo, h))));
    return tint_ * (transmitted * ggx::D(h.z, alpha_) * ggx::G2(wo.z, mirrored.z, alpha_) / (4.0f * wo.z));
  }
  // Walter et al. 2007, eq. 21 with IOR 1 on wo's side and eta on wi's: the generalised half
  // vector, on wo's side, must see wo in front and wi behind.
  vec3 h = wo + eta_ * wi;
  const float hl = glm::length(h);
  if (!(hl > 1e-7f)) return vec3(0.0f);
  h /= hl;
  if (h.z < 0.0f) h = -h;
  const float cos_oh = glm::dot(wo, h), cos_ih = glm::dot(wi, h);
  if (cos_oh <= 0.0f || cos_ih >= 0.0f) return vec3(0.0f);
  const float transmitted = 1.0f - maxComponent(fresnel(cos_oh));
  const float denom = cos_oh + eta_ * cos_ih;
  const float f = -cos_ih * cos_oh / wo.z * transmitted * ggx::D(h.z, alpha_) * ggx::G2(wo.z, -wi.z, alpha_) /
                  (denom * denom);
  return tint_ * f;
}

float DielectricBsdf::pdfLocal(const vec3& wo, const vec3& wi) const {
  if (delta_ || wo.z <= 0.0f || wi.z == 0.0f) return 0.0f;
  // Visible normals: pdf(h) = G1(wo) D(h) (wo.h) / wo.z; then the lobe choice max(F) and the
  // Jacobian of h -> wi.
  if (wi.z > 0.0f || thin_) {
    const vec3 w = wi.z > 0.0f ? wi : vec3(wi.x, wi.y, -wi.z);
    const vec3 h = glm::normalize(wo + w);
    const float reflect = maxComponent(fresnel(std::max(0.0f, glm::dot(wo, h))));
    const float choice = wi.z > 0.0f ? reflect : 1.0f - reflect;
    return choice * ggx::G1(wo.z, alpha_) * ggx::D(h.z, alpha_) / (4.0f * wo.z);
  }
  vec3 h = wo + eta_ * wi;
  const float hl = glm::length(h);
  if (!(hl > 1e-7f)) return 0.0f;
  h /= hl;
  if (h.z < 0.0f) h = -h;
  const float cos_oh = glm::dot(wo, h), cos_ih = glm::dot(wi, h);
  if (cos_oh <= 0.0f || cos_ih >= 0.0f) return 0.0f;
  const float transmit = 1.0f - maxComponent(fresnel(cos_oh));
  const float denom = cos_oh + eta_ * cos_ih;
  const float pdf_h = ggx::G1(wo.z, alpha_) * ggx::D(h.z, alpha_) * cos_oh / wo.z;
  return transmit * pdf_h * eta_ * eta_ * -cos_ih / (denom * denom);
}

vec3 DielectricBsdf::eval(const vec3& wo, const vec3& wi) const {
  return evalLocal(frame_.toLocal(wo), frame_.toLocal(wi));
}

float DielectricBsdf::pdf(const vec3& wo, const vec3& wi) const {
  return pdfLocal(frame_.toLocal(wo), frame_.toLocal(wi));
}

std::optional<BsdfSample> DielectricBsdf::sample(const vec3& wo_world, const vec3& u) const {
  const vec3 wo = frame_.toLocal(wo_world);
  if (wo.z <= 0.0f) return std::nullopt;
  BsdfSample s;
  s.dielectric = true;
  if (delta_) {
    const vec3 f = fresnel(wo.z);
    const float reflect = maxComponent(f);
    s.delta = true;
    vec3 wi;
    if (u.x < reflect) {
      wi = vec3(-wo.x, -wo.y, wo.z);
      s.weight = f / reflect;
    } else {
      // 1 - max(F) transmitted, chosen with that probability; radiance scales by 1/eta^2
      // (IOR 1 on wo's side), except through a thin wall, which it leaves on the IOR it came in.
      const auto refracted = thin_ ? std::optional<vec3>(-wo) : refractDirection(wo, vec3(0, 0, 1), eta_);
      if (!refracted) return std::nullopt;
      wi = *refracted;
      s.weight = thin_ ? tint_ : tint_ / (eta_ * eta_);
      s.transmitted = true;
    }
    s.wi = glm::normalize(frame_.toWorld(wi));
    return s;
  }
  const vec3 h = ggx::sampleVisibleNormal(wo, alpha_, {u.y, u.z});
  const float cos_oh = glm::dot(wo, h);
  if (!(cos_oh > 0.0f)) return std::nullopt;
  const float reflect = maxComponent(fresnel(cos_oh));
  vec3 wi;
  if (u.x < reflect) {
    wi = glm::reflect(-wo, h);
    if (wi.z <= 0.0f) return std::nullopt;
  } else if (thin_) {
    wi = glm::reflect(-wo, h);
    wi.z = -wi.z;
    if (wi.z >= 0.0f) return std::nullopt;
  } else {
    const auto refracted = refractDirection(wo, h, eta_);
    if (!refracted || refracted->z >= 0.0f) return std::nullopt;
    wi = *refracted;
  }
  s.pdf = pdfLocal(wo, wi);
  if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
  s.weight = evalLocal(wo, wi) / s.pdf;
  if (!isFinite(s.weight)) return std::nullopt;
  s.wi = glm::normalize(frame_.toWorld(wi));
  s.transmitted = wi.z < 0.0f;
  return s;
}

MaterialBsdf::MaterialBsdf(const SurfaceMaterial& material, const vec3& normal, bool front,
                           const vec3& clearcoat_normal)
    : transmissive_(finiteMaterial(material) ? (1.0f - std::clamp(material.metallic, 0.0f, 1.0f)) *
                                                   std::clamp(material.transmission, 0.0f, 1.0f)
                                             : 0.0f),
      clearcoat_(finiteMaterial(material) ? std::clamp(material.clearcoat, 0.0f, 1.0f) : 0.0f),
      thin_(material.thin_walled),
      opaque_(opaqueBase(material, transmissive_), normal),
      coat_(clearcoatLayer(material), clearcoat_normal),
      glass_(material, normal, 1.0f, vec3(1.0f), material.thin_walled) {
  const float ior = std::isfinite(material.ior) ? std::max(material.ior, 1.0f) : 1.5f;
  if (transmissive_ > 0.0f && !thin_ && !front) {
    // Inside the volume: the interface alone, towards IOR 1.
    transmissive_ = 1.0f;
    clearcoat_ = 0.0f;
    glass_ = DielectricBsdf(material, normal, 1.0f / ior, vec3(1.0f), false);
  } else if (transmissive_ > 0.0f) {
    glass_ = DielectricBsdf(material, normal, ior, glm::clamp(material.base_colour, vec3(0.0f), vec3(1.0f)),
                            thin_);
  }
}

float MaterialBsdf::baseScale(const vec3& wo) const {
  if (clearcoat_ <= 0.0f) return 1.0f;
  return 1.0f - clearcoat_ * schlickCoat(std::max(0.0f, glm::dot(coat_.normal(), wo)));
}

void MaterialBsdf::lobeProbabilities(const vec3& wo, float p[3]) const {
  p[0] = clearcoat_ > 0.0f ? clearcoat_ * schlickCoat(std::max(0.0f, glm::dot(coat_.normal(), wo))) : 0.0f;
  const float base = 1.0f - p[0];
  p[1] = base * (1.0f - transmissive_);
  p[2] = base * transmissive_;
}

bool MaterialBsdf::hasNonDelta() const {
  const bool coat = clearcoat_ > 0.0f && !coat_.mirror();
  const bool opaque = transmissive_ < 1.0f && (!opaque_.mirror() || opaque_.hasDiffuse());
  const bool glass = transmissive_ > 0.0f && !glass_.delta();
  return coat || opaque || glass;
}

vec3 MaterialBsdf::eval(const vec3& wo, const vec3& wi) const {
  vec3 base(0.0f);
  if (transmissive_ < 1.0f) base += (1.0f - transmissive_) * opaque_.eval(wo, wi);
  if (transmissive_ > 0.0f) base += transmissive_ * glass_.eval(wo, wi);
  if (clearcoat_ <= 0.0f) return base;
  return baseScale(wo) * base + clearcoat_ * coat_.eval(wo, wi);
}

float MaterialBsdf::pdf(const vec3& wo, const vec3& wi) const {
  float p[3];
  lobeProbabilities(wo, p);
  float pdf = 0.0f;
  if (p[0] > 0.0f) pdf += p[0] * coat_.pdf(wo, wi);
  if (p[1] > 0.0f) pdf += p[1] * opaque_.pdf(wo, wi);
  if (p[2] > 0.0f) pdf += p[2] * glass_.pdf(wo, wi);
  return pdf;
}

std::optional<BsdfSample> MaterialBsdf::sample(const vec3& wo, const vec3& u) const {
  float p[3];
  lobeProbabilities(wo, p);
  // Pick a lobe with u.x and hand it u.x rescaled to [0, 1), so one lobe alone sees u unchanged.
  int lobe = 0;
  float start = 0.0f;
  while (lobe < 2 && (p[lobe] <= 0.0f || u.x >= start + p[lobe])) {
    start += p[lobe];
    ++lobe;
  }
  if (!(p[lobe] > 0.0f)) return std::nullopt;
  const vec3 u_lobe(std::clamp((u.x - start) / p[lobe], 0.0f, 0.99999994f), u.y, u.z);
  std::optional<BsdfSample> s = lobe == 0   ? coat_.sample(wo, u_lobe)
                                : lobe == 1 ? opaque_.sample(wo, u_lobe)
                                            : glass_.sample(wo, u_lobe);
  if (!s) return std::nullopt;
  if (s->delta) {
    // A delta lobe is this lobe's alone: its value times its weight in the mixture.
    const float scale =
        lobe == 0 ? clearcoat_ : baseScale(wo) * (lobe == 1 ? 1.0f - transmissive_ : transmissive_);
    s->weight *= scale / p[lobe];
    if (!isFinite(s->weight)) return std::nullopt;
    return s;
  }
  if (p[lobe] == 1.0f) return s;  // one lobe: its own weight is the mixture's
  s->pdf = pdf(wo, s->wi);
  if (!(s->pdf > 0.0f) || !std::isfinite(s->pdf)) return std::nullopt;
  s->weight = eval(wo, s->wi) / s->pdf;
  if (!isFinite(s->weight)) return std::nullopt;
  return s;
}

}  // namespace holo::reference
