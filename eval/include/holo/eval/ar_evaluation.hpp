// The AR composite measured on the simulated museum (ar/local_path_tracing.hpp; the comparison of
// Xu et al.). The truth: the relic placed in the simulated hall, seen by a simulated camera, path
// traced. The hall's surfaces within `local_radius` of the pyramid frame's origin are Lambertian
// with their material's base colour as albedo (clamped to kTrueAlbedoMax), lit by the museum's
// panorama at infinity (the distant hall); nothing else is there. The camera's colour image is the
// real scene alone path traced at truth_spp through the sensor model (sim::applySensorNoise:
// colour noise and 8-bit sRGB), its depth the sensor model's depth of the hall; the composite is
// made from those two images only (ar/ar_view.hpp's steps: depth surface, albedo estimate).
//
// The rig's four cameras look outward from the base and never see the relic, so the measuring
// camera is a check camera in the hall looking at the relic (eye, look_at, vfov_deg).
//
// Error: on the displayed images (linearToSrgb of the camera's exposure times the radiance, in
// 8-bit codes, so the panorama's lamps in the relic's reflections weigh as they are seen), the
// RMS over the RGB channels of the difference to the truth over the region the relic changes: its
// pixels in the truth, and the pixels whose luminance it changes by more than region_threshold of
// the real scene's (its shadow and its light). Whatever a composite leaves out there counts. Also
// over the shadow part alone (the real pixels of the region, where the two methods differ) and
// over the whole image (where the relic changes nothing, a composite should add nothing).
// Methods at equal time: delta path tracing at method_spp samples (relic_spp_factor times that on
// the pixels where the relic is seen), then each two-pass differential
// renderer (independent samples, and shared samples: ar/local_path_tracing.hpp) given as many
// 1-spp passes as fit in the same CPU time (the process's threads, all cores together, so other
// load on the machine does not count; at least one pass), all unfiltered (the comparison of Xu et
// al.), all shading the relic's pixels alike and all tracing only the pixels the relic can change
// (ar/change_region.hpp, its time counted in delta path tracing's); and the product's composite,
// delta path tracing with its change filtered (ar/change_filter.hpp), which the adversary (the
// relic over the camera's image, the real surfaces unchanged) is measured against.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "holo/core/math.hpp"

namespace holo::eval {

inline constexpr float kTrueAlbedoMax = 0.9f;

struct ArEvaluationOptions {
  std::string scene = "museum";
  std::string relic;  // built-in name or glTF file; empty: the scene's
  int width = 320, height = 180;
  float vfov_deg = 40.0f;
  vec3 eye{0.35f, 0.55f, 1.05f};
  vec3 look_at{0.0f, 0.08f, 0.0f};
  float local_radius = 1.5f;
  int panorama_width = 512;
  int truth_spp = 256;
  int method_spp = 8;
  // Delta path tracing's relic pixels take this many times method_spp samples
  // (ar::CompositeSettings::relic_spp_factor); the plain two-pass renderers sample every pixel
  // alike, and are measured again with the same split (two_pass_split, two_pass_shared_split).
  int relic_spp_factor = 4;
  int max_bounces = 3;
  int delta_bounces = 3;  // delta path tracing's real levels (ar::CompositeSettings)
  float region_threshold = 0.02f;
  bool sensor_noise = true;
  // The real surfaces' albedo estimated from the colour (ar/albedo_estimate.hpp); false: a grey of
  // 0.5 everywhere instead (what the estimate is measured against).
  bool estimate_albedo = true;
  // Every method's relic pixels take a real surface the camera sees at the camera's radiance
  // (ar::renderComposite's depth); false: the local scene's model of it path traced.
  bool measured_real_radiance = true;
  std::uint64_t seed = 1;
  // A small bright lamp added to the hall's panorama (5 degrees in radius, this radiance; 0: none),
  // towards `lamp_direction` (world, from the relic): what focuses a glass relic's caustic.
  float lamp_radiance = 0.0f;
  vec3 lamp_direction{-0.3f, 0.8f, -0.5f};
  // The two-pass renderers' budget: equal CPU time (the evaluation), or, when false, at least the
  // delta path tracer's count of rays (deterministic, for tests).
  bool equal_time = true;
};

struct ArErrors {
  double region = 0;  // RMSE, 8-bit codes, over the relic and what it changes
  double relic = 0;   // over the region's relic pixels (those the relic covers in the truth)
  double shadow = 0;  // over the region's real pixels
  double image = 0;   // over the whole image
};

struct ArMethodScore {
  ArErrors rmse;
  double ms = 0;  // CPU time (all threads together)
  int spp = 0;
  std::int64_t rays = 0;
};

struct ArEvaluation {
  cv::Mat truth;          // CV_32FC3 linear BGR, the mixed scene path traced
  cv::Mat camera_colour;  // CV_8UC3: the real scene as the camera delivers it
  cv::Mat region;         // CV_8UC1 255 where the error is measured
  cv::Mat shadow;         // CV_8UC1 255 on the region's pixels that see no relic
  cv::Mat relic;          // CV_8UC1 255 on the region's pixels that see the relic
  cv::Mat delta_composite, two_pass_composite, two_pass_shared_composite, filtered_composite,
      no_shadow_composite;  // CV_32FC3
  ArMethodScore delta, two_pass, two_pass_shared, filtered;
  // The two-pass renderers given delta path tracing's relic_spp_factor too (at equal time).
  ArMethodScore two_pass_split, two_pass_shared_split;
  ArErrors no_shadow;  // the adversary: the relic pasted over the image, no change
  // Delta path tracing's composite with the region's real pixels set to the truth: what its relic
  // pixels alone leave (shaded alike by every method), so two_pass.rmse.region over this region
  // error is the largest ratio any gain on the real pixels could give.
  ArErrors delta_relic_alone;
  // The truth's own path tracer on the exact local scene (the hall's surfaces, not the camera's
  // depth and colour) at delta path tracing's samples per pixel (its relic pixels' count there),
  // seeded apart from the truth: the
  // error that sampling alone leaves at that count, against which the relic's pixels are read.
  ArErrors exact_scene;
  // A transmissive relic only: the product's composite with the relic's glass opaque.
  std::optional<ArErrors> glass_opaque;
  cv::Mat glass_opaque_composite;  // CV_32FC3
  // A transmissive relic standing on the base: the relic's caustic (ar/relic_caustic.hpp) is in
  // delta path tracing's composites; photons traced for it (0: none), and the product's composite
  // without its light tracer (the caustic left to BSDF sampling alone), the caustic's pixels
  // (CV_8UC1 255: real pixels the truth shows above 1.5x the camera's image) and the error there.
  std::uint64_t caustic_photons = 0;
  std::optional<ArErrors> without_light_tracer;
  cv::Mat without_light_tracer_composite;  // CV_32FC3
  cv::Mat caustic;
  int caustic_pixels = 0;
  double caustic_rmse = 0, caustic_rmse_without_light_tracer = 0;  // 8-bit codes over `caustic`
  // The mean change of linear luminance over the region's real pixels (its shadow and light)
  // against the camera's true image: the truth's, the product's, without the light tracer.
  double shadow_change_truth = 0, shadow_change = 0, shadow_change_without_light_tracer = 0;
  int region_pixels = 0, relic_pixels = 0, shadow_pixels = 0;
  int traced_pixels = 0;  // the pixels delta path tracing traced (ar::changeRegion)
  float exposure = 1.0f;
};

ArEvaluation evaluateArComposite(const ArEvaluationOptions& options);

// RMSE in 8-bit codes of the displayed `image` against the displayed `truth` (both CV_32FC3
// radiance, shown at `exposure`) over the pixels where `mask` (CV_8UC1) is set; 0 for none.
double displayedRmse(const cv::Mat& image, const cv::Mat& truth, const cv::Mat& mask, float exposure);

}  // namespace holo::eval
