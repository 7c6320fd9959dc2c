// Diffuse lighting from an environment: its radiance projected on the 9 real spherical
// harmonics of bands 0-2 and convolved with the clamped cosine (Ramamoorthi & Hanrahan 2001).
// The projection integrates the panorama pixel by pixel (pixel-centre direction times the
// pixel's exact solid angle), so a radiance that is a polynomial of degree <= 2 in the direction
// gives its irradiance to within the panorama's quadrature error (~1e-4 at 256x128).
#pragma once

#include <array>

#include "holo/reflect/environment.hpp"

namespace holo::reflect {

class IrradianceSH {
 public:
  IrradianceSH() = default;
  explicit IrradianceSH(const Environment& environment);
  // Irradiance E(n) = integral of L(w) max(0, n.w) dw (RGB, clamped at 0); a white Lambert
  // surface reflects E / pi.
  vec3 irradiance(const vec3& normal) const;
  const std::array<vec3, 9>& coefficients() const { return c_; }

 private:
  std::array<vec3, 9> c_{};  // radiance coefficients L_lm, RGB
};

}  // namespace holo::reflect
