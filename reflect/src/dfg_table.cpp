#include "holo/reflect/dfg_table.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "holo/reflect/bsdf.hpp"

namespace holo::reflect {

namespace {

constexpr int kTableSize = 32;
constexpr int kTableSamples = 1024;

float radicalInverse(std::uint32_t i) {
  i = (i << 16u) | (i >> 16u);
  i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
  i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
  i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
  i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
  return float(i) * 2.3283064365386963e-10f;
}

float cellNdotV(int i) {
  return (float(i) + 0.5f) / float(kTableSize);
}
float cellRoughness(int j) {
  return float(j) / float(kTableSize - 1);
}

const std::array<vec2, kTableSize * kTableSize>& table() {
  static const auto t = [] {
    std::array<vec2, kTableSize * kTableSize> out{};
    for (int j = 0; j < kTableSize; ++j)
      for (int i = 0; i < kTableSize; ++i)
        out[std::size_t(j) * kTableSize + i] = dfgIntegrate(cellNdotV(i), cellRoughness(j), kTableSamples);
    return out;
  }();
  return t;
}

}  // namespace

vec2 dfgIntegrate(float n_dot_v, float roughness, int samples) {
  const float c = std::clamp(n_dot_v, 1e-4f, 1.0f);
  const vec3 wo(std::sqrt(1.0f - c * c), 0.0f, c);
  if (roughness < kDeltaRoughness) {
    const float s = std::pow(1.0f - c, 5.0f);
    return {1.0f - s, s};
  }
  const float alpha = roughnessToAlpha(roughness);
  // Visible-normal sampling: weight f cos / pdf = G2 / G1(wo), times Fresnel.
  double a = 0, b = 0;
  for (int k = 0; k < samples; ++k) {
    const vec2 u((float(k) + 0.5f) / float(samples), radicalInverse(std::uint32_t(k)));
    const vec3 h = ggx::sampleVisibleNormal(wo, alpha, u);
    const vec3 wi = glm::reflect(-wo, h);
    if (wi.z <= 0.0f) continue;
    const float weight = ggx::G2(wo.z, wi.z, alpha) / ggx::G1(wo.z, alpha);
    const float s = std::pow(1.0f - std::clamp(glm::dot(wo, h), 0.0f, 1.0f), 5.0f);
    a += double(weight * (1.0f - s));
    b += double(weight * s);
  }
  return {float(a / samples), float(b / samples)};
}

vec2 dfg(float n_dot_v, float roughness) {
  if (roughness < kDeltaRoughness) return dfgIntegrate(n_dot_v, roughness, 1);
  const auto& t = table();
  const float fi = std::clamp(n_dot_v * kTableSize - 0.5f, 0.0f, float(kTableSize - 1));
  const float fj = std::clamp(roughness, 0.0f, 1.0f) * float(kTableSize - 1);
  const int i0 = std::min(int(fi), kTableSize - 2), j0 = std::min(int(fj), kTableSize - 2);
  const float ti = fi - float(i0), tj = fj - float(j0);
  const auto at = [&](int i, int j) { return t[std::size_t(j) * kTableSize + i]; };
  return (1 - tj) * ((1 - ti) * at(i0, j0) + ti * at(i0 + 1, j0)) +
         tj * ((1 - ti) * at(i0, j0 + 1) + ti * at(i0 + 1, j0 + 1));
}

}  // namespace holo::reflect
