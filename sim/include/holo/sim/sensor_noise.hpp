// The depth-camera sensor model: turns what a perfect sensor sees (true depth, the angle of
// incidence, radiance) into what a consumer RGB-D camera delivers. Documented in docs/sim.md
// ("Sensor model", "Sensor profiles"). The uniform profile:
//   * depth noise: Gaussian with sigma(z) = sigma_0 + k_z1 z + k_z2 z^2 (metres; z = camera-frame
//     depth); the structured-light profile then quantises it in disparity,
//   * dropouts: beyond the grazing angle (ray vs. surface normal), a random fraction everywhere,
//     and a fraction of the pixels on depth edges,
//   * flying pixels: some remaining edge pixels take a depth between the two sides of the edge,
//   * colour: sRGB 8-bit of exposure * radiance plus Gaussian noise of color_sigma steps,
//   * measured depths outside [min_range, max_range] become 0 (invalid).
// The structured-light and stereo profiles (SensorProfile in museum.hpp) replace the random and
// edge dropouts by holes in patches: the projector's (second camera's) shadow, traced per row from
// the true depth; then, per pixel, a keep probability from the incidence angle, the range, a dark
// or metal surface, a smooth surface's highlight, a nearby depth edge and (stereo) low texture, compared with
// smooth value noise that is partly fixed per camera and partly new each frame; structured light quantises
// depth in disparity. Every random number comes from a counter-based generator keyed by (seed, stream,
// pixel), so the result never depends on how rows are split between threads.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "holo/sim/museum.hpp"

namespace holo::sim {

// Deterministic random numbers for one pixel (SplitMix64 over a hash of the key).
class PixelRng {
 public:
  PixelRng(std::uint64_t seed, std::uint64_t stream, int x, int y);
  std::uint64_t next();
  float uniform();  // [0, 1)
  float normal();   // standard normal (Box-Muller)

 private:
  std::uint64_t state_;
};

// Standard deviation of the depth noise at camera-frame depth z (metres).
float depthSigma(const SensorNoise& noise, float z);

// A depth edge: a 4-neighbour is invalid or differs by more than 0.05 m + 5% of z.
bool isDepthEdge(const cv::Mat& true_depth, int x, int y);

// What the surface seen by each pixel is made of (its Material), for the structured-light and
// stereo profiles' dark, metal and highlight holes. Empty maps: the radiance's luminance stands
// in for the albedo and nothing is metal or glossy.
struct SurfaceMaps {
  cv::Mat albedo;     // CV_32FC1 luminance of the base colour, [0, 1]
  cv::Mat metallic;   // CV_32FC1 [0, 1]
  cv::Mat roughness;  // CV_32FC1 [0, 1] perceptual
};

struct SensorOutput {
  cv::Mat depth;   // CV_32FC1 metres, 0 = invalid
  cv::Mat colour;  // CV_8UC3 BGR sRGB
};

// Applies the sensor model. true_depth: CV_32FC1 (0 = nothing in range); cos_incidence: CV_32FC1
// |cos| of the angle between the pixel's ray and the surface normal; radiance: CV_32FC3 BGR linear.
// With noise.enabled == false the depth is the truth and the colour is noiseless. `seed` keys
// everything that changes every frame; `static_seed` (one per camera) the part of the
// structured-light and stereo hole patterns that stays put, so holes flicker only partly, as
// real ones do. `surface`: the materials under the pixels (all three maps, or none). Parallel over rows
// (oneTBB), bit-identical for the same inputs and seeds.
SensorOutput applySensorNoise(const SensorNoise& noise, const CameraSettings& camera,
                              const cv::Mat& true_depth, const cv::Mat& cos_incidence,
                              const cv::Mat& radiance, std::uint64_t seed, std::uint64_t static_seed = 0,
                              const SurfaceMaps& surface = {});

}  // namespace holo::sim
