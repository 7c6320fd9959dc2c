// The environment beyond the scene: an equirectangular linear HDR panorama (CV_32FC3 BGR) seen
// from infinitely far away, with its importance-sampling distribution built once.
//
// Direction <-> pixel: core/equirect.hpp is the one mapping (with the calibrated yaw). Radiance
// is piecewise constant per pixel (nearest pixel), exactly the function the distribution
// samples, so light-sampling estimates are unbiased and a single bright pixel stays a single
// bright pixel. Sampling picks a pixel with probability proportional to
// max(R,G,B) * (pixel solid angle), then a direction uniformly in solid angle inside the pixel
// (uniform in longitude and in cos(colatitude)); the pdf is per unit solid angle and constant
// over a pixel, so radiance / pdf is bounded by the panorama's total power (no fireflies from
// the sampling itself). Invariants: pixels finite and >= 0 (repaired and counted on
// construction); an all-black panorama is valid and samples nothing.
#pragma once

#include <cstdint>

#include "holo/core/image.hpp"
#include "holo/reflect/distribution.hpp"

namespace holo::reflect {

struct EnvironmentSample {
  vec3 direction{0.0f, 1.0f, 0.0f};  // world, unit, pointing away from the scene
  vec3 radiance{0.0f};               // linear RGB
  float pdf = 0.0f;                  // per steradian; 0 = no sample (all-black environment)
};

class Environment {
 public:
  Environment() = default;
  // Copies the panorama; yaw in radians as in core/equirect.hpp.
  explicit Environment(const cv::Mat& panorama_bgr32f, float yaw = 0.0f);
  // A constant environment (the white furnace); small, exact.
  static Environment uniform(const vec3& radiance, int width = 64, int height = 32);

  vec3 radiance(const vec3& direction) const;  // nearest pixel, RGB
  EnvironmentSample sample(const vec2& u) const;
  float pdf(const vec3& direction) const;  // pdf of sample() at this direction
  bool black() const { return distribution_.empty(); }

  // Integral of radiance over the sphere (RGB, W/m^2 per unit radiance scale).
  vec3 integral() const { return integral_; }
  const cv::Mat& panorama() const { return panorama_; }
  float yaw() const { return yaw_; }
  std::uint64_t contentHash() const { return hash_; }  // changes whenever the pixels or yaw do
  const RepairCounts& repaired() const { return repaired_; }

  // Row y's colatitude span [theta0, theta1] and a pixel's solid angle (exact, steradians).
  static double pixelSolidAngle(int y, int width, int height);

 private:
  ivec2 pixelOf(const vec3& direction) const;
  cv::Mat panorama_;
  float yaw_ = 0.0f;
  Distribution2D distribution_;
  std::vector<double> row_solid_angle_;
  vec3 integral_{0.0f};
  std::uint64_t hash_ = 0;
  RepairCounts repaired_;
};

}  // namespace holo::reflect
