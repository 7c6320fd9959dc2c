// The panorama's sun: its small, very bright region, found from the pixels, so the renderer can
// take it out of the 9-coefficient diffuse light (which holds a point-like light's clamped cosine
// only to order 2: ~9% of its peak at the terminator, 6% on the far side) and light the relic
// with it as a directional light, its exact clamped cosine and a shadow ray (sun_light.hpp in
// reflect/src).
//
// Found as the 8-connected region (wrapping round in longitude) of pixels around the brightest
// one whose luminance exceeds `threshold_ratio` times the panorama's mean (solid-angle weighted).
// Its light is what it holds above the pixels bordering it (their mean radiance, the sky the sun
// stands in): the excess radiance times each pixel's solid angle. A sun is found when the region
// is no larger than `max_solid_angle` and its excess carries at least `min_share` of the
// panorama's light (luminance times solid angle); an interior's lamps and windows are too wide or
// too weak to pass. Units: radiance in, irradiance (W/m^2 per unit radiance) out; the directions
// in the panorama's world frame (its yaw applied), unit.
#pragma once

#include <array>
#include <string>

#include "holo/reflect/environment.hpp"

namespace holo::reflect {

struct SunSearchSettings {
  float threshold_ratio = 20.0f;  // a sun pixel's luminance over the panorama's mean, > 1
  float max_solid_angle = 0.02f;  // steradians (the sun is 6.8e-5; a blurred HDR sun ~1e-3)
  float min_share = 0.15f;        // of the panorama's light, (0, 1]
};

struct PanoramaSun {
  bool found = false;
  vec3 direction{0.0f, 1.0f, 0.0f};  // towards the sun: the excess's luminance-weighted centroid
  float solid_angle = 0.0f;          // steradians of the region
  vec3 power{0.0f};                  // integral of the excess radiance: the irradiance it gives a
                                     // surface facing it, RGB
  float share = 0.0f;                // the excess's share of the panorama's light (luminance)
  int pixels = 0;                    // in the region
  float peak_ratio = 0.0f;           // the brightest pixel's luminance over the panorama's mean
  // The excess's radiance on the 9 real spherical harmonics (irradiance_sh.hpp's basis): what the
  // diffuse light's coefficients hold of it.
  std::array<vec3, 9> radiance_sh{};
  // "sun at 38 deg elevation, 4.1e-3 sr, 71% of the light" or why none was found.
  std::string describe() const;
  // The sun's part of a GGX lobe prefiltered about unit `direction` (lobe_integral.hpp's W, the
  // prefiltered IBL's lobe) at perceptual `roughness` > 0, the sun taken as a point: power W(l) /
  // integral W.
  vec3 lobe(const vec3& direction, float roughness) const;
};

PanoramaSun findPanoramaSun(const Environment& environment, const SunSearchSettings& settings = {});

}  // namespace holo::reflect
