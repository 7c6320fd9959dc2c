#include "holo/reflect/optics.hpp"

#include <algorithm>
#include <cmath>

namespace holo::reflect {

float fresnelDielectric(float cos_i, float eta) {
  cos_i = std::isfinite(cos_i) ? std::clamp(cos_i, 0.0f, 1.0f) : 0.0f;
  if (!std::isfinite(eta) || !(eta > 0.0f)) eta = 1.0f;
  const float sin2_t = refractedSin2(cos_i, eta);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  const float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float f = 0.5f * (rs * rs + rp * rp);
  return std::isfinite(f) ? std::clamp(f, 0.0f, 1.0f) : 1.0f;
}

float refractedSin2(float cos_i, float eta) {
  const float c = std::clamp(cos_i, 0.0f, 1.0f);
  return (1.0f - c * c) / (eta * eta);
}

vec3 snellRefraction(const vec3& d, const vec3& n, float eta, float cos_i) {
  const float cos_t = std::sqrt(std::max(0.0f, 1.0f - refractedSin2(cos_i, eta)));
  return d / eta + (cos_i / eta - cos_t) * n;
}

std::optional<vec3> refractDirection(const vec3& wo, const vec3& h, float eta) {
  const float cos_o = glm::dot(wo, h);
  if (refractedSin2(cos_o, eta) >= 1.0f) return std::nullopt;
  return glm::normalize(snellRefraction(-wo, h, eta, cos_o));
}

vec3 refractIncident(const vec3& d, const vec3& n, float eta) {
  const vec3 t = snellRefraction(d, n, eta, std::clamp(-glm::dot(d, n), 0.0f, 1.0f));
  const float len = glm::length(t);
  return len > 1e-12f ? t / len : d;
}

vec3 attenuationCoefficient(const vec3& colour, float distance) {
  if (!(distance > 0.0f) || !std::isfinite(distance)) return vec3(0.0f);
  vec3 sigma;
  for (int k = 0; k < 3; ++k) {
    const float c = std::clamp(colour[k], 0.0f, 1.0f);
    sigma[k] = c > 0.0f ? std::min(-std::log(c) / distance, kOpaqueAbsorption) : kOpaqueAbsorption;
  }
  return sigma;
}

vec3 transmittance(const vec3& sigma, float distance) {
  return glm::exp(-sigma * distance);
}

}  // namespace holo::reflect
