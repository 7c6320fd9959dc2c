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
  // From radiance coefficients L_lm (RGB), e.g. an environment's less a light taken out of it.
  explicit IrradianceSH(const std::array<vec3, 9>& radiance) : c_(radiance) {}
  // Irradiance E(n) = integral of L(w) max(0, n.w) dw (RGB, clamped at 0); a white Lambert
  // surface reflects E / pi.
  vec3 irradiance(const vec3& normal) const;
  const std::array<vec3, 9>& coefficients() const { return c_; }
  // The coefficients of L'(d) = L(turn(d)), turn(d) = (c x + s z, y, c z - s x) with c = cos a,
  // s = sin a: the same light seen from a frame turned by -a about the vertical.
  std::array<vec3, 9> turnedAboutY(float cos_a, float sin_a) const;

  // The 9 real basis functions at a unit direction (index l^2 + l + m).
  static std::array<float, 9> basis(const vec3& d);
  // The clamped cosine's convolution factor per coefficient (pi, 2 pi / 3, pi / 4 by band): the
  // irradiance of a unit normal n is sum_i kCosineLobe[i] L_i basis(n)[i].
  static constexpr std::array<float, 9> kCosineLobe = {
      kPi,        2.0f * kPi / 3.0f, 2.0f * kPi / 3.0f, 2.0f * kPi / 3.0f, kPi / 4.0f,
      kPi / 4.0f, kPi / 4.0f,        kPi / 4.0f,        kPi / 4.0f};

 private:
  std::array<vec3, 9> c_{};  // radiance coefficients L_lm, RGB
};

}  // namespace holo::reflect
