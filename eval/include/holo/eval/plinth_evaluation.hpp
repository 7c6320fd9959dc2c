// `eval plinth` (docs/tracer/caustics.md): a glass relic on a virtual plinth in a hall lit by one
// small bright lamp over a dim sky, one pyramid view: ours (the live renderer, its plinth drawn
// with the relic's shadow and, for a transmissive relic, the live light tracer's caustic) against
// the path-traced truth (`render --method gt`, the plinth a Lambert surface of the relic's), the
// error stated over the plinth's pixels (those whose primary ray meets the plinth before the
// relic, or misses the relic), beside two adversaries: ours with the caustic off (the plinth
// takes the relic's full shadow), and ours without the relic's shadow and caustic at all.
// Units: metres, degrees, linear radiance.
#pragma once

#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"
#include "holo/eval/reflection_scene.hpp"

namespace holo::eval {

struct PlinthEvaluationOptions {
  std::string relic = "glass-sphere";  // glass-sphere (the caustic scene's sphere) or a built-in relic
  int size = 64;                       // the view's width and height, pixels
  int truth_spp = 256;
  std::uint64_t caustic_photons = 1u << 20;
  float lamp_angle_deg = 20.0f;   // the lamp's direction from the vertical, towards +x
  float lamp_radius_deg = 5.0f;   // its angular radius
  float lamp_radiance = 2000.0f;  // linear, every channel
  float sky_radiance = 0.3f;      // the rest of the panorama
  std::uint64_t seed = 1;
};

// The scene: the relic fitted (glass-sphere: radius 5 cm, centre 7.5 cm over the plinth's top),
// the panorama, the plinth (half width 0.15 m, height 0.1 m, albedo 0.7), no hall, no visitors.
ReflectionScene plinthScene(const PlinthEvaluationOptions& options);
CameraModel plinthCamera(const ReflectionScene& scene, int size);

struct PlinthEvaluation {
  cv::Mat truth, ours, ours_no_caustic, ours_unshadowed;  // linear HDR BGR
  cv::Mat plinth_mask;                                    // CV_8U, 255 on the plinth's pixels
  int plinth_pixels = 0;
  // Relative RMSE over the plinth's pixels: sqrt(mean |ours - truth|^2) / mean(truth) (luminance).
  double error = 0, error_no_caustic = 0, error_unshadowed = 0;
  // The same over the caustic's pixels: plinth pixels where the truth is brighter than the
  // unshadowed plinth (light the relic focuses there); 0 pixels for an opaque relic.
  int caustic_pixels = 0;
  double caustic_error = 0, caustic_error_no_caustic = 0;
  std::uint64_t photons_traced = 0, photons_stored = 0;
  double ours_ms = 0, caustic_ms = 0;  // ours: the view with its plinth relit (first frame)
};

PlinthEvaluation evaluatePlinth(const PlinthEvaluationOptions& options);

}  // namespace holo::eval
