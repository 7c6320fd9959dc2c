#include "holo/reflect/bsdf.hpp"

#include <algorithm>
#include <cmath>

namespace holo::reflect {

namespace ggx {

float D(float cos_theta_h, float alpha) {
  if (cos_theta_h <= 0.0f) return 0.0f;
  const float a2 = alpha * alpha;
  const float c2 = cos_theta_h * cos_theta_h;
  // (1 - c2) + c2 a2 rather than c2 (a2 - 1) + 1: the latter rounds to 0 at the peak of a very
  // sharp lobe (a2 < float epsilon), which would make D infinite.
  const float d = std::max(0.0f, 1.0f - c2) + c2 * a2;
  return a2 / (kPi * d * d);
}

float lambda(float cos_theta, float alpha) {
  const float c2 = std::max(cos_theta * cos_theta, 1e-12f);
  const float tan2 = std::max(0.0f, 1.0f - c2) / c2;
  return 0.5f * (std::sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
}

float G1(float cos_theta, float alpha) {
  if (cos_theta <= 0.0f) return 0.0f;
  return 1.0f / (1.0f + lambda(cos_theta, alpha));
}

float G2(float cos_o, float cos_i, float alpha) {
  if (cos_o <= 0.0f || cos_i <= 0.0f) return 0.0f;
  return 1.0f / (1.0f + lambda(cos_o, alpha) + lambda(cos_i, alpha));
}

vec3 sampleVisibleNormal(const vec3& wo, float alpha, const vec2& u) {
  const vec3 vh = glm::normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));
  const float len2 = vh.x * vh.x + vh.y * vh.y;
  const vec3 t1 = len2 > 0.0f ? vec3(-vh.y, vh.x, 0.0f) / std::sqrt(len2) : vec3(1, 0, 0);
  const vec3 t2 = glm::cross(vh, t1);
  const float r = std::sqrt(u.x);
  const float phi = 2.0f * kPi * u.y;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1.0f + vh.z);
  const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * std::sin(phi);
  const vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(vec3(alpha * nh.x, alpha * nh.y, std::max(1e-7f, nh.z)));
}

vec3 sampleNormal(float alpha, const vec2& u) {
  // tan^2(theta) = alpha^2 u / (1 - u), written in cos^2 to stay finite for u -> 1.
  const float a2 = alpha * alpha;
  const float cos2 = (1.0f - u.x) / (1.0f + (a2 - 1.0f) * u.x);
  const float cos_t = std::sqrt(std::clamp(cos2, 0.0f, 1.0f));
  const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
  const float phi = 2.0f * kPi * u.y;
  return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}

}  // namespace ggx

vec3 schlickFresnel(const vec3& f0, float cos_theta) {
  const float m = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0 + (vec3(1.0f) - f0) * (m2 * m2 * m);
}

float roughnessToAlpha(float roughness) {
  const float r = std::clamp(roughness, 0.0f, 1.0f);
  return r * r;
}

Frame::Frame(const vec3& normal) : n(normal) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b2 = n.x * n.y * a;
  t = vec3(1.0f + sign * n.x * n.x * a, sign * b2, -sign * n.x);
  b = vec3(b2, sign + n.y * n.y * a, -n.y);
}

vec3 dielectricF0(float ior, const vec3& specular_colour) {
  double r2 = 1.0;  // +infinity
  if (std::isnan(ior)) {
    r2 = 0.04;  // ((1.5 - 1) / (1.5 + 1))^2, the glTF default
  } else if (std::isfinite(ior)) {
    const double n = std::max(double(ior), 1.0);
    const double r = (n - 1.0) / (n + 1.0);
    r2 = r * r;
  }
  vec3 f0;
  for (int k = 0; k < 3; ++k) {
    const double c = r2 * double(specular_colour[k]);
    f0[k] = c > 0.0 ? float(std::min(c, 1.0)) : 0.0f;  // NaN and negative to 0
  }
  return f0;
}

namespace {

float schlickWeight(float cos_theta) {
  const float m = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
  const float m2 = m * m;
  return m2 * m2 * m;
}

vec3 cosineSampleHemisphere(const vec2& u) {
  const float r = std::sqrt(u.x);
  const float phi = 2.0f * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u.x))};
}

}  // namespace

Bsdf::Bsdf(const SurfaceMaterial& material, const vec3& normal)
    : m_(material),
      f0_(dielectricF0(material.ior, material.specular_colour)),
      frame_(normal),
      alpha_(roughnessToAlpha(material.roughness)),
      delta_(material.roughness < kDeltaRoughness) {
  m_.base_colour = glm::clamp(m_.base_colour, vec3(0.0f), vec3(1.0f));
  m_.metallic = std::clamp(m_.metallic, 0.0f, 1.0f);
  m_.specular = std::clamp(m_.specular, 0.0f, 1.0f);
}

bool Bsdf::hasDiffuse() const {
  return m_.metallic < 1.0f && luminance(m_.base_colour) > 0.0f;
}

// Fresnel of the dielectric layer and of the whole specular lobe at cos(v, h).
vec3 Bsdf::dielectricFresnel(float c) const {
  return m_.specular * (f0_ + (1.0f - f0_) * schlickWeight(c));
}
vec3 Bsdf::specularFresnel(float c) const {
  return (1.0f - m_.metallic) * dielectricFresnel(c) + m_.metallic * schlickFresnel(m_.base_colour, c);
}

// Probability of sampling the specular lobe: its Fresnel-weighted share at the view angle.
float Bsdf::specularProbability(float cos_o) const {
  const float spec = luminance(specularFresnel(cos_o));
  const float diff =
      (1.0f - m_.metallic) * (1.0f - maxComponent(dielectricFresnel(cos_o))) * luminance(m_.base_colour);
  if (spec + diff <= 0.0f) return 1.0f;
  return std::clamp(spec / (spec + diff), 0.0f, 1.0f);
}

vec3 Bsdf::evalLocal(const vec3& wo, const vec3& wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return vec3(0.0f);
  vec3 h = wo + wi;
  const float hl = glm::length(h);
  if (!(hl > 1e-8f)) return vec3(0.0f);
  h /= hl;
  const float c = std::max(0.0f, glm::dot(wo, h));
  // The extension's fresnel_mix: the diffuse keeps what the strongest channel leaves.
  const vec3 diffuse =
      (1.0f - m_.metallic) * (1.0f - maxComponent(dielectricFresnel(c))) * m_.base_colour * (wi.z / kPi);
  if (delta_) return diffuse;
  // f_spec * cos_i = F D G2 / (4 cos_o cos_i) * cos_i
  const float spec = ggx::D(h.z, alpha_) * ggx::G2(wo.z, wi.z, alpha_) / (4.0f * wo.z);
  return diffuse + specularFresnel(c) * spec;
}

float Bsdf::pdfLocal(const vec3& wo, const vec3& wi, float p_spec) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  float pdf = (1.0f - p_spec) * wi.z / kPi;
  if (!delta_) {
    vec3 h = wo + wi;
    const float hl = glm::length(h);
    if (hl > 1e-8f) {
      h /= hl;
      // Visible-normal pdf: G1(wo) D(h) (wo.h) / wo.z, times the reflection Jacobian 1/(4 wo.h).
      pdf += p_spec * ggx::G1(wo.z, alpha_) * ggx::D(h.z, alpha_) / (4.0f * wo.z);
    }
  }
  return pdf;
}

vec3 Bsdf::eval(const vec3& wo, const vec3& wi) const {
  return evalLocal(frame_.toLocal(wo), frame_.toLocal(wi));
}

float Bsdf::pdf(const vec3& wo, const vec3& wi) const {
  const vec3 o = frame_.toLocal(wo);
  if (o.z <= 0.0f) return 0.0f;
  return pdfLocal(o, frame_.toLocal(wi), specularProbability(o.z));
}

std::optional<BsdfSample> Bsdf::sample(const vec3& wo_world, const vec3& u) const {
  const vec3 wo = frame_.toLocal(wo_world);
  if (wo.z <= 0.0f) return std::nullopt;
  const float p_spec = specularProbability(wo.z);
  BsdfSample s;
  vec3 wi;
  if (u.x < p_spec) {
    if (delta_) {
      wi = vec3(-wo.x, -wo.y, wo.z);
      s.wi = frame_.toWorld(wi);
      s.weight = specularFresnel(wo.z) / p_spec;
      s.delta = true;
      return s;
    }
    const vec3 h = ggx::sampleVisibleNormal(wo, alpha_, {u.y, u.z});
    wi = glm::reflect(-wo, h);
  } else {
    wi = cosineSampleHemisphere({u.y, u.z});
  }
  if (wi.z <= 0.0f) return std::nullopt;
  s.pdf = pdfLocal(wo, wi, p_spec);
  if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
  s.wi = glm::normalize(frame_.toWorld(wi));
  s.weight = evalLocal(wo, wi) / s.pdf;
  if (!isFinite(s.weight)) return std::nullopt;
  return s;
}

}  // namespace holo::reflect
