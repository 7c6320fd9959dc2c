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
// The structured-light and stereo profiles (SensorProfile below) replace the random and
// edge dropouts by holes in patches: the projector's (second camera's) shadow, traced per row from
// the true depth; then, per pixel, a keep probability from the incidence angle, the range, a dark
// or metal surface, a smooth surface's highlight, a nearby depth edge and (stereo) low texture, compared with
// smooth value noise that is partly fixed per camera and partly new each frame; structured light quantises
// depth in disparity. Every random number comes from a counter-based generator keyed by (seed, stream,
// pixel), so the result never depends on how rows are split between threads.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace holo::sim {

// Which kind of depth camera the sensor model imitates (docs/sim.md, "Sensor profiles").
//   uniform          : Gaussian noise, holes at grazing angles, on depth edges and scattered at
//                      random (salt-like).
//   structured-light : Kinect-like, fitted to real TUM RGB-D frames: the projector's shadow beside
//                      depth edges, holes in patches on dark, metal, glossy and glancing surfaces
//                      and towards the range limit, disparity quantisation, holes that flicker
//                      frame to frame. Every built-in scene's and scene file's default.
//   stereo           : ZED-like: holes in patches on low-texture surfaces, the second camera's
//                      occlusion beside depth edges, foreground fattened over the background.
enum class SensorProfile { uniform, structured_light, stereo };

struct SensorNoise {
  SensorProfile profile = SensorProfile::uniform;
  // Depth noise standard deviation sigma(z) = sigma_0 + k_z1 * z + k_z2 * z^2 (metres).
  float sigma_0 = 0.001f;
  float k_z1 = 0.0f;
  float k_z2 = 0.0025f;
  float grazing_dropout_deg = 78.0f;  // beyond this angle between ray and normal, no depth
  float edge_dropout = 0.5f;          // probability of dropping a pixel on a depth edge
  float flying_pixel = 0.3f;          // probability an edge pixel takes a mixed depth
  float random_dropout = 0.01f;       // probability any pixel has no depth
  float colour_sigma = 2.0f;          // colour noise, 8-bit steps
  bool enabled = true;

  // The structured-light and stereo profiles only (the uniform profile ignores these).
  // Projector-camera (or camera-camera) baseline along the image +x axis, metres: pixels the
  // projector (second camera) cannot see have no depth.
  float baseline = 0.075f;
  // Disparity is measured in steps of disparity_step_px at native_focal_px (the sensor's own
  // resolution, whatever the image's): depth comes in steps of z^2 * step / (focal * baseline).
  float native_focal_px = 580.0f;
  float disparity_step_px = 0.125f;
  float grazing_start_deg = 60.0f;  // hole probability ramps from 0 here to 1 at grazing_dropout_deg
  // Surfaces whose albedo luminance (without a material: the radiance's luminance) is below
  // dark_luminance lose up to dark_dropout of their pixels: all of it at albedo 0, none at the
  // threshold (the projector's infrared comes back too weak from dark clothes and hair).
  float dark_luminance = 0.0f;
  float dark_dropout = 0.0f;
  // Metal returns no diffuse pattern: a pixel on it is lost with probability metal_dropout x
  // metallic x (1 - roughness) (brushed metal scatters some of it back).
  float metal_dropout = 0.0f;
  // A smooth surface (roughness below 0.5) seen within highlight_deg of head-on mirrors the
  // projector into the camera and saturates it: up to highlight_dropout lost, all of it at
  // roughness 0 and head-on, fading to none at roughness 0.5 and at highlight_deg.
  float highlight_deg = 0.0f;
  float highlight_dropout = 0.0f;
  float range_fade_start = 20.0f;  // hole probability ramps from 0 here to 1 at range_fade_end
  float range_fade_end = 20.0f;
  float edge_band_px = 1.0f;          // edge_dropout applies within this many pixels of a depth edge
  float low_texture_contrast = 0.0f;  // stereo: 7x7 sRGB contrast (8-bit steps) below which ...
  float low_texture_dropout = 0.0f;   // ... pixels lose depth with this probability
  float edge_fattening_px = 0.0f;     // stereo: foreground depth spreads this far over the background
  float hole_patch_px = 8.0f;         // holes come in patches about this wide
  float hole_flicker = 0.3f;          // share of the patch pattern that changes every frame
};

// "uniform", "structured-light", "stereo"; sensorProfileFromName throws InputError(origin,
// field, ...) for another name.
const char* sensorProfileName(SensorProfile profile);
SensorProfile sensorProfileFromName(const std::string& name, const std::string& origin = "",
                                    const std::string& field = "sensor");
std::vector<std::string> sensorProfileNames();
// The profile's parameters (fitted ones for structured-light).
SensorNoise sensorProfile(SensorProfile profile);

struct CameraSettings {
  int width = 640;
  int height = 360;
  float hfov_deg = 110.0f;
  float vfov_deg = 70.0f;
  // Upwards tilt of the optical axis. 8 degrees sees the heads of visitors >= ~1 m away; a visitor
  // standing within ~0.6 m of the pyramid shows only from the waist to the chest: a rig for close
  // visitors needs more (eval tracer uses 20 degrees with vfov 90).
  float tilt_deg = 8.0f;
  float min_range = 0.2f;
  float max_range = 20.0f;
  float fps = 30.0f;
  float exposure = 1.0f;
};

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
