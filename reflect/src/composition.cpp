#include "holo/reflect/composition.hpp"

#include <algorithm>
#include <cmath>

namespace holo::reflect {
namespace {

vec3 sanitize(const vec3& c) {
  vec3 out;
  for (int k = 0; k < 3; ++k) out[k] = std::isfinite(c[k]) && c[k] > 0.0f ? c[k] : 0.0f;
  return out;
}

}  // namespace

vec3 composeReflection(const vec3& psi_d, const vec3& psi_s, float w) {
  const float weight = std::isfinite(w) ? std::clamp(w, 0.0f, 1.0f) : 0.0f;
  return sanitize(psi_d) * weight + sanitize(psi_s) * (1.0f - weight);
}

}  // namespace holo::reflect
