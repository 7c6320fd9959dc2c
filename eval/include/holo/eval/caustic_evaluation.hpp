// `eval caustics` (docs/tracer/caustics.md): a glass sphere over a diffuse plane under a small
// bright light. The photon map (reference/caustics.hpp) against a converged light tracer of the
// same scene (another seed, many more photons): the caustic's peak position and its power on
// the disc of one sphere radius round the light tracer's peak. The closed forms beside them:
// the peak lies where the line from the light through the sphere's centre meets the plane (the
// scene is symmetric about it), and a ball lens focuses paraxial light at n R / (2 (n - 1))
// from its centre. The same scene with an opaque sphere runs no caustic work. Beside them the live
// light tracer the pyramid views use (reflect/caustic_tracer.hpp), measured the same way.
#pragma once

#include <cstdint>

#include "holo/core/mesh.hpp"
#include "holo/reference/caustics.hpp"

namespace holo::eval {

struct CausticScene {
  float radius = 0.05f;  // sphere, metres
  float ior = 1.5f;
  float centre_height = 0.075f;   // sphere centre above the plane y = 0, metres
  float light_distance = 1.0f;    // from the sphere's centre, metres
  float light_angle_deg = 20.0f;  // from the vertical, towards +x
  float light_power = 100.0f;     // W per RGB channel
};

struct CausticEvaluationOptions {
  CausticScene scene;
  std::uint64_t photons = 200000;             // the photon map's
  std::uint64_t reference_photons = 4000000;  // the light tracer's
  int resolution = 200;                       // cells along the receiver's side
  float kernel_radius_over_radius = 0.04f;    // the photon map's kernel, in sphere radii
  std::uint64_t seed = 1;                     // the light tracer uses seed + 1
  bool opaque = false;                        // the sphere opaque (metal) instead of glass
  // The live light tracer's photons (reflect/caustic_tracer.hpp, seed + 2); 0: not run.
  std::uint64_t live_photons = 1u << 20;
};

// A glass (or, opaque, a mirror-metal) sphere mesh of the scene, wound counter-clockwise seen
// from outside (128 rings of 256 segments).
Model causticSphere(const CausticScene& scene, bool opaque);
reference::PointLight causticLight(const CausticScene& scene);
reference::CausticReceiver causticReceiver(const CausticScene& scene);
// Where the line from the light through the sphere's centre meets the plane, (x, z).
vec2 causticAxisPoint(const CausticScene& scene);

struct CausticEvaluation {
  reference::CausticPlan plan;
  reference::ReceiverImage photon_map;
  reference::ReceiverImage light_tracer;
  std::int64_t photons_traced = 0;  // the counter "Caustics/Photons traced" over the run
  std::int64_t photons_stored = 0;
  vec2 peak{0.0f}, reference_peak{0.0f}, axis_point{0.0f};
  double power = 0, reference_power = 0;  // W (luminance) on the disc of one radius round reference_peak
  // Mean irradiance (W/m^2, luminance) on the disc of 0.1 radius round reference_peak: what a
  // blurring kernel flattens, which the peak position and the power on the disc barely see.
  double peak_irradiance = 0, reference_peak_irradiance = 0;
  double peakIrradianceRatio() const {
    return reference_peak_irradiance > 0 ? peak_irradiance / reference_peak_irradiance : 0.0;
  }
  double peakErrorOverRadius(float radius) const { return glm::length(peak - reference_peak) / radius; }
  double powerError() const {
    return reference_power > 0 ? std::abs(power - reference_power) / reference_power : 1.0;
  }
  // The live light tracer's estimate on the same grid, measured as the photon map's.
  reference::ReceiverImage live;
  vec2 live_peak{0.0f};
  double live_power = 0, live_peak_irradiance = 0, live_ms = 0;
  std::uint64_t live_photons_stored = 0;
  double livePeakErrorOverRadius(float radius) const {
    return glm::length(live_peak - reference_peak) / radius;
  }
  double livePowerError() const {
    return reference_power > 0 ? std::abs(live_power - reference_power) / reference_power : 1.0;
  }
};

// The receiver's whole irradiance for a figure: `caustic` plus the light's direct irradiance
// (cosine over distance squared, shadowed by the sphere), W/m^2, CV_32FC3 BGR.
cv::Mat receiverIrradiance(const CausticScene& scene, bool opaque, const reference::ReceiverImage& caustic);

// Runs the photon map and the light tracer; the light tracer's photons in batches (bounded memory).
CausticEvaluation evaluateCaustics(const CausticEvaluationOptions& options);

}  // namespace holo::eval
