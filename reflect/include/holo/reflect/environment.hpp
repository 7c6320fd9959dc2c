// The environment beyond the scene: an equirectangular linear HDR panorama (CV_32FC3 BGR), with
// its importance-sampling distribution built once. By default the panorama is seen from
// infinitely far away (every point of the scene reads direction d's pixel for direction d). A
// hall is not infinitely far: with a finite PanoramaProxy the panorama's pixels lie on a sphere
// of the hall's size around the point where it was captured, and a ray from p reads the pixel
// of the direction from that point to where the ray meets the sphere (parallax).
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

#include <cmath>
#include <cstdint>
#include <limits>

#include "holo/core/image.hpp"
#include "holo/reflect/distribution.hpp"

namespace holo::reflect {

// Where the panorama's pixels are. radius: metres from `centre` (the capture point, world frame)
// to the hall's walls; infinite = at infinity (the default, no parallax). Points the lookup is
// asked about should lie inside the sphere; from outside it (or with an infinite radius) the
// lookup falls back to the ray's own direction. base_half_width (metres, >= 0; 0 = none): the
// pyramid's square base, its top the plane y = 0 of the world (pyramid) frame, |x|, |z| <= the
// half width; where it is nearer than the sphere (below a relic, and below a capture point
// above it) the panorama's pixels lie on it: it hides the hall behind it.
struct PanoramaProxy {
  vec3 centre{0.0f};
  float radius = std::numeric_limits<float>::infinity();
  float base_half_width = 0.0f;

  bool infinite() const { return !std::isfinite(radius); }
  // The panorama direction a ray from `origin` along unit `direction` reads.
  vec3 lookupDirection(const vec3& origin, const vec3& direction) const;
  // Where the panorama's pixel of (unit) direction d lies: the proxy seen from the centre.
  vec3 point(const vec3& d) const;
  // Solid-angle density at `origin` over density at the centre, for the point q of the proxy the
  // ray from `origin` along `direction` meets: |q - origin|^2 cos_centre / (|q - centre|^2
  // cos_origin), the cosines between the proxy's normal at q and the two rays (on the sphere
  // |q - origin|^2 / (R^2 cos)): pdf conversion. 1 when infinite.
  float solidAngleRatio(const vec3& origin, const vec3& direction) const;
};

struct EnvironmentSample {
  vec3 direction{0.0f, 1.0f, 0.0f};  // world, unit, pointing away from the scene
  vec3 radiance{0.0f};               // linear RGB
  float pdf = 0.0f;                  // per steradian; 0 = no sample (all-black environment)
};

class Environment {
 public:
  Environment() = default;
  // Copies the panorama; yaw in radians as in core/equirect.hpp. Throws InputError when the
  // proxy's radius is not positive or its centre not finite.
  explicit Environment(const cv::Mat& panorama_bgr32f, float yaw = 0.0f, PanoramaProxy proxy = {});
  // A constant environment (the white furnace); small, exact.
  static Environment uniform(const vec3& radiance, int width = 64, int height = 32);

  // Seen from the capture point (or from anywhere when the proxy is infinite).
  vec3 radiance(const vec3& direction) const;  // nearest pixel, RGB
  EnvironmentSample sample(const vec2& u) const;
  float pdf(const vec3& direction) const;  // pdf of sample() at this direction
  // Seen from `origin` through the proxy: the same three, per unit solid angle at `origin`.
  vec3 radiance(const vec3& origin, const vec3& direction) const;
  EnvironmentSample sample(const vec2& u, const vec3& origin) const;
  float pdf(const vec3& origin, const vec3& direction) const;
  const PanoramaProxy& proxy() const { return proxy_; }
  bool black() const { return distribution_.empty(); }

  // Integral of radiance over the sphere (RGB, W/m^2 per unit radiance scale).
  vec3 integral() const { return integral_; }
  const cv::Mat& panorama() const { return panorama_; }
  float yaw() const { return yaw_; }
  std::uint64_t contentHash() const { return hash_; }  // changes whenever the pixels, yaw or proxy do
  const RepairCounts& repaired() const { return repaired_; }

  // Row y's colatitude span [theta0, theta1] and a pixel's solid angle (exact, steradians).
  static double pixelSolidAngle(int y, int width, int height);

 private:
  ivec2 pixelOf(const vec3& direction) const;
  cv::Mat panorama_;
  float yaw_ = 0.0f;
  PanoramaProxy proxy_;
  Distribution2D distribution_;
  std::vector<double> row_solid_angle_;
  vec3 integral_{0.0f};
  std::uint64_t hash_ = 0;
  RepairCounts repaired_;
};

}  // namespace holo::reflect
