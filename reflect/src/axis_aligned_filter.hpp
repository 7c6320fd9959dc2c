// Axis-aligned filtering (Mehta et al. 2015, Sec. 6.5 and 7, after Mehta et al. 2013) of the one
// low-sample Monte Carlo term of the live renderer: the rough lobe's interreflection
// (static_shading.hpp), whose strata are traced a quarter per pixel and summed by a 3x3 tent. The
// rest of the static shading (split-sum IBL, diffuse irradiance, the mirror-ray bounce of smoother
// materials, the transmitted light read from the prefiltered IBL at its derived roughness) has no
// sampling noise and is not touched.
//
// Per pixel, the spatial bandwidth of the interreflected light is B = B_h / z_min (the paper's
// eq. 18, 1/metres): B_h the BRDF's angular bandlimit, 4.27 + 0.15 m for a Phong lobe of exponent m
// (the GGX alpha = roughness^2 read as m = 2 / alpha^2 - 2), z_min the nearest hit distance (metres)
// of the pixel's own lobe rays that met the relic, or where none of them did, of the 3x3 tent's.
// Where none of those met it, z_min is infinite and B = 0: the term is the same everywhere the
// filter reaches. The filter is the paper's two separable passes
// along the image's X then Y axis (eqs. 21, 22) with the Gaussian weight exp(-2 B^2 |p - p'|^2) of
// the world positions (eq. 23, B^2 the mean of the two pixels' squares), over pixels of the same
// surface only: a neighbour that does not trace the lobe, faces away by more than ~25 degrees, or
// lies off the pixel's tangent plane (a depth edge) gets no weight. The radius covers 2.5 standard
// deviations (1 / (2 B)) at the pixel's footprint, at most kMaxRadius pixels.
//
// What is filtered are the lobe's sums (rays above the surface, rays that met the relic, their
// second points' diffuse and specular light), so the pixel's own specular scale (its texture and
// Fresnel) multiplies the filtered ratios afterwards and is never blurred.
#pragma once

#include <cstdint>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "lobe_bounce.hpp"

namespace holo::reflect {

struct FilterCounts {
  std::uint64_t pixels = 0;  // pixels whose lobe term was filtered
  std::uint64_t taps = 0;    // neighbour weights taken, both passes
  double ms = 0.0;           // wall time of the filter
};

class AxisAlignedFilter {
 public:
  static constexpr int kMaxRadius = 8;  // pixels each side, per pass

  // B_h: the angular bandlimit of a GGX lobe of this perceptual roughness (MWRD13's Phong fit).
  static float brdfBandwidth(float roughness);
  // B = B_h / z_min, 1/metres; 0 for an infinite (or non-finite) z_min.
  static float bandwidth(float roughness, float nearest_hit);

  // Filters `bounces` (per pixel, row-major, width x height: the tent-pooled lobe sums) in place,
  // at the pixels that trace the lobe (pixels[p].rough); the others are left as they were.
  // pixels[p] gives the position, normal, roughness and its own lobe rays' nearest hit; `view`
  // the pixel footprint.
  FilterCounts apply(const std::vector<PixelBounce>& pixels, std::vector<LobeBounce>& bounces, int width,
                     int height, const CameraModel& view) const;
};

}  // namespace holo::reflect
