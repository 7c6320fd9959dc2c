// Per-camera blurred foreground pyramids (paper Section 3.3): rho_gamma, the foreground colour,
// and rho_g, the foreground mask, with `levels` (l_max) levels built by the dual Kawase filter
// (Kawase 2003; Bjorge 2015's downsampling form): level l+1 is level l filtered with the Kawase
// 5-tap kernel (the 2x2 block centre, weight 4/8, plus four diagonal taps one pixel out, 1/8 each,
// every tap a bilinear read) and halved in resolution.
//
// Colour is stored premultiplied by the mask, so background pixels never bleed into the
// foreground's blur; sample() divides it back out: radiance = blur(colour * mask) / blur(mask),
// weight = blur(mask). The composition then reads psi_d * w = blur(colour * mask).
//
// Blur scale (derived in docs/tracer/voxel_walk.md): one Kawase step has per-axis variance 3/4 of its input
// pixel, so level L has variance sigma^2(L) = sum_{l<L} (3/4) 4^l = (4^L - 1) / 4 in level-0
// pixels; reading level L bilinearly adds a tent of width 2^L (variance 4^L / 6), so a read
// delivers sigma^2(L) = (5/12) 4^L - 1/4 and the level for a wanted sigma is
// L = log2((sigma^2 + 1/4) 12/5) / 2 (clamped at 0). tests/reflect/test_foreground_pyramid.cpp
// measures it on an impulse.
//
// Support: premultiplied colour and mask are exactly 0 where the blurred mask cannot reach, so
// each level is filtered only over the mask's bounding box grown by the Kawase footprint at that
// level (support(level)); the rest of the level stays 0. The result equals the full-image build
// (tests/reflect/test_foreground_pyramid.cpp compares them); a small visitor costs a small box.
// Units: pixels of the camera image (level 0), linear radiance.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/math.hpp"

namespace holo::reflect {

inline constexpr int kMaxPyramidLevels = 12;

struct ForegroundSample {
  vec3 radiance{0.0f};  // linear RGB of the foreground around the pixel (0 where weight is 0)
  float weight = 0.0f;  // blurred mask, [0, 1]
};

class ForegroundPyramid {
 public:
  ForegroundPyramid() = default;
  // colour: CV_32FC3 linear BGR; mask: CV_32FC1 in [0, 1] or CV_8UC1 (0..255), same size.
  // Non-finite colours count as 0 and non-finite mask values as 0 (repairs, not errors).
  // Throws InputError when the types or sizes disagree or levels is outside 1..kMaxPyramidLevels.
  ForegroundPyramid(const cv::Mat& colour_bgr, const cv::Mat& mask, int levels);

  // Rebuilds in place (same contract as the constructor). The level images are reused when the
  // image size and level count are unchanged, so a per-frame rebuild allocates no level images.
  void build(const cv::Mat& colour_bgr, const cv::Mat& mask, int levels);
  // Makes the pyramid empty (sample() returns weight 0) but keeps its buffers for the next build.
  void clear() { levels_ = 0; }

  int levels() const { return levels_; }
  bool empty() const { return levels_ == 0; }
  // Bilinear read at a level-0 pixel position (integer = pixel centre) with a continuous level
  // clamped to [0, levels-1] (linear between the two nearest levels). Outside the image: clamped.
  ForegroundSample sample(const vec2& pixel, float level) const;
  // Level images, 0 <= level < levels() (throws std::out_of_range otherwise).
  const cv::Mat& premultipliedColour(int level) const { return colour_.at(checkedLevel(level)); }
  const cv::Mat& mask(int level) const { return mask_.at(checkedLevel(level)); }
  // The level's pixels that may be non-zero (in that level's pixels); every pixel outside is 0.
  // Empty when the mask is empty.
  const cv::Rect& support(int level) const { return support_.at(checkedLevel(level)); }

 private:
  std::size_t checkedLevel(int level) const;

  int levels_ = 0;
  std::vector<cv::Mat> colour_;    // CV_32FC3, colour * mask; may hold more than levels_ (kept buffers)
  std::vector<cv::Mat> mask_;      // CV_32FC1
  std::vector<cv::Rect> support_;  // per level, the region written by the last build
  cv::Mat filtered_colour_, filtered_mask_;  // Kawase filter scratch, reused across builds
};

// The Kawase pyramid's blur: per-axis standard deviation (level-0 pixels) of a continuous level,
// and its inverse (the level giving a wanted sigma, >= 0).
float pyramidSigmaPx(float level);
float pyramidLevelForSigma(float sigma_px);

// Per-axis angular standard deviation (radians) of a GGX reflection lobe around the mirror
// direction, from perceptual roughness (alpha = roughness^2): sqrt(2) * alpha, from the Beckmann
// slope variance alpha^2 / 2 per axis and the doubling of angles by reflection; capped at 1 rad.
float reflectedLobeSigma(float roughness);

// The pyramid level for a reflected ray: its lobe, spread over the travel distance from the hit
// point to the voxel (metres), seen by a camera at distance camera_distance (metres) with focal
// length focal_px, covers sigma = travel * tan(lobe) * focal_px / camera_distance pixels.
// Non-finite or non-positive inputs give level 0 (a mirror read); the result is in [0, levels-1].
float foregroundLevel(float roughness, float travel_m, float camera_distance_m, float focal_px, int levels);
// The same for a lobe of per-axis angular standard deviation lobe_sigma_rad (capped at 1 rad).
float foregroundLevelForLobe(float lobe_sigma_rad, float travel_m, float camera_distance_m, float focal_px,
                             int levels);

// GGX's lobe is heavy-tailed where one Gaussian is not: its slopes follow a 2D Student t with 2
// degrees of freedom, P(m) = 1 / (pi alpha^2 (1 + |m|^2 / alpha^2)^2), which is a scale mixture
// of Gaussians: per-axis slope variance alpha^2 / G with G ~ chi^2(2). reflectedLobeSigma takes
// G's mean (2, Beckmann's alpha^2 / 2). A mixture of `components` Gaussians splits G's
// distribution into equal-probability bins and takes each bin's median: component k has weight
// 1 / components and sigma reflectedLobeSigma(roughness) * sqrt(2 / G_k). One component is
// G = 2 itself (reflectedLobeSigma). components in 1..kMaxLobeComponents.
inline constexpr int kMaxLobeComponents = 8;
struct LobeComponent {
  float sigma_scale = 1.0f;  // times reflectedLobeSigma
  float weight = 1.0f;       // the weights sum to 1
};
std::vector<LobeComponent> ggxLobeMixture(int components);

}  // namespace holo::reflect
