// The integral of a panorama against the GGX lobe the prefiltered IBL stands for (Karis'
// split-sum assumption, normal = view = n):
//   I(n) = integral L(l) W(l) dl / integral W(l) dl,   W(l) = D(h) / 4 * max(0, n.l),
// with L the panorama's pixel-constant radiance (Environment's convention). The prefilter calls
// it once per texel of every rough level; tests compare it with the sum over every pixel.
//
// Method: adaptive quadrature on a MIP pyramid of the panorama kept in its own equirectangular
// pixels (no resampling; a level k + 1 pixel is the union of up to 2 x 2 level k pixels). A
// pixel is one quadrature point unless it is nearer to n than `tail_ratio` times its own angular
// extent or overlaps the lobe's core (2 alpha radians), in which case its children are used
// instead; the descent stops at the coarsest level whose pixels are at most
// `core_ratio * alpha` radians wide (the core is about 1.3 alpha half width). The GGX tail falls as angle^-4,
// so a pixel of extent s at angle t from n sees the weight vary by about 4 s / t: far pixels may be coarse,
// and a texel costs about 2 pi tail_ratio^2 ln(pi / (core_ratio alpha)) weight evaluations instead of one per
// pixel. Each pixel's radiance is placed at its power centroid (luminance-weighted) and its solid angle at
// its geometric centroid, so a sun inside a coarse pixel stays where it is (a point light is integrated
// exactly at any level) and a uniform panorama gives exactly its radiance. Units: radiance in, radiance out;
// angles in radians.
#pragma once

#include <vector>

#include "holo/core/image.hpp"
#include "holo/core/math.hpp"

namespace holo::reflect {

// W(l) up to a constant factor (it cancels in every ratio), with normal = view: (n.h)^2 =
// (1 + n.l) / 2, so D(h) ~ 1 / (1 - (1 + n.l) k1)^2 needs no square root.
inline float ggxLobeK1(float alpha) {
  return 0.5f * (1.0f - alpha * alpha);
}
inline float ggxLobeWeight(float cos_nl, float k1) {
  if (!(cos_nl > 0.0f)) return 0.0f;
  const float d = 1.0f - (1.0f + cos_nl) * k1;
  return cos_nl / (d * d);
}

struct LobeQuadratureOptions {
  // Split a pixel nearer than this many of its extents to n (> 0); 4 is within ~0.3% of the
  // pixel sum, 1.5 (the prefilter's) within ~1.2% mean, at under half the cost (measured).
  float tail_ratio = 4.0f;
  float core_ratio = 0.6f;  // finest pixels needed: core_ratio * alpha radians wide (> 0)
};

class GgxLobeIntegral {
 public:
  GgxLobeIntegral() = default;
  // panorama: CV_32FC3 BGR, finite and >= 0 (an Environment's); yaw as in core/equirect.hpp.
  GgxLobeIntegral(const cv::Mat& panorama_bgr32f, float yaw, LobeQuadratureOptions options = {});

  // The quadrature for one GGX alpha (> 0): which pyramid levels, how near a pixel must be to
  // be split. Cheap; make one per lobe, reuse it for every direction.
  struct Lobe {
    float k1 = 0.0f;               // ggxLobeK1(alpha), for ggxLobeWeight
    int finest = 0;                // pyramid level where the descent stops
    std::vector<float> split_cos;  // per level: split a pixel whose centroid has n.c above this
  };
  Lobe lobe(float alpha) const;

  // I(n) for a unit direction n; black when the panorama is.
  vec3 integrate(const vec3& n, const Lobe& lobe) const;
  int levelCount() const { return static_cast<int>(levels_.size()); }

 private:
  struct Pixel {
    vec3 centroid;   // solid-angle centroid, unit
    float omega;     // solid angle, sr
    vec3 power_dir;  // luminance-weighted centroid, unit (the centroid when black)
    vec3 power;      // radiance x solid angle, RGB
  };
  struct Level {
    int width = 0, height = 0;
    float extent = 0.0f;  // largest angular side of a pixel, radians
    std::vector<Pixel> pixels;
  };
  LobeQuadratureOptions options_;
  std::vector<Level> levels_;  // [0] = the panorama itself
};

}  // namespace holo::reflect
