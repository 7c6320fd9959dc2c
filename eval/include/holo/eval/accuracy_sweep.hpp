// Accuracy against time (`holopyramid bench accuracy`, docs/tracer/evaluation.md). On one scene of the tracer
// evaluation (a hall x relic with its walkers and visitors close to the pyramid, the view where the
// visitors matter most: visitorView) it sweeps each method's quality knobs,
//   ours   anti-aliasing (1, 4) x pyramid levels (5, 7, 9) x voxel size (2, 3.125, 5 cm), the
//          pyramid level offset -1 / +1 around the derived level, 1 or 4 Gaussians for the GGX
//          lobe instead of 2, the default tracer with each effect of the plan switched
//          (effectVariants: that effect's point), on a relic that samples its rough lobe the
//          default tracer without the axis-aligned filter at 6x6 and 8x8 strata too (the
//          filter's time spent on samples instead); on a
//          transmissive relic also the refraction pass's internal depth (1, 2, 4, 8, 16 interface
//          events against the measured one) and the transmitted lobe's width (its derived
//          roughness x 0, 0.5, 2: the IBL level and pyramid levels it reads) and the pixels
//          between traced transmitted paths (refraction_stride 1..4) and the rays a path may
//          spend following light reflected inside at an exit (0, 2, 16);
//   ibl    the paper's IBL (visitors reprojected into the panorama, prefiltered every frame) at
//          6, 8, 10 roughness levels;
//   ssrt   1, 2, 4, 8, 16 rays per hit point;
//   mcpt   path tracing of the reconstructed scene, 1, 2, 4, ... max_spp samples per pixel;
// and scores each against the path-traced truth (scoring.hpp: fg_mse on the displayed images).
// Times are milliseconds per view, the per-frame work amortised over the four face views; the
// median of `repeats` runs.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace holo::eval {

struct AccuracyOptions {
  std::string hall = "gallery", relic = "vase";  // built-in hall and relic
  int size = 64;                                 // view width and height, pixels
  // Rough reflections converge slowly: at 512 spp the truth's noise is a large part of the
  // kettle's fg_mse (eval tracer's gt noise column, docs/tracer/evaluation.md).
  int gt_spp = 4096;
  int max_spp = 256;
  int repeats = 3;
  int close_visitors = 1;
  std::string visitor_model;          // "bodies" or "figures" (sim/visitors.hpp); empty = the hall's own
  bool panorama_at_infinity = false;  // as SceneOptions::panorama_at_infinity
  float camera_tilt_deg = 20.0f, camera_vfov_deg = 90.0f;  // eval tracer's rig for close visitors
  std::string cache =
      (std::filesystem::temp_directory_path() / "holopyramid-gt-cache").string();  // ground truths
  // Only ours' effect points (effectVariants): no quality knob, no other method.
  bool effects_only = false;
};

// The default tracer with one effect of the plan switched: "default" (every effect where the plan
// wants it, the eye moving: no refinement), "SelfOcclusion off" (the unoccluded irradiance),
// "RoughLobe off" (the interreflection along the mirror ray at every roughness), "VisitorLight
// off", "AxisAlignedFilter off" (the rough lobe's strata unfiltered), "ProgressiveRefinement on"
// (kRefinementStillFrames frames with nothing moving after the default's frame).
std::vector<std::string> effectVariants();
// About 2 s of refining frames at the live frame rate (docs/tracer/progressive_refinement.md).
inline constexpr int kRefinementStillFrames = 9;

struct AccuracyPoint {
  std::string method, knob;
  std::string effect;  // ours: its effectVariants() name; "" for a quality knob's point
  std::string plan;    // ours: its frame's effect plan (EffectPlan::describe)
  double ms = 0, fg_mse = 0, mse = 0;
  bool pareto = false;  // no other point is at most as slow and as wrong, and better in one
};

struct AccuracySweep {
  int frame = 0, face = 0;  // the view picked
  int region_pixels = 0;    // of the foreground region; 0: every fg_mse is 0
  std::vector<AccuracyPoint> points;
};

// Throws InputError for a hall or relic that is not built in.
AccuracySweep sweepAccuracy(const AccuracyOptions& options);

// fg_mse against milliseconds per view, log-log, the Pareto front joined, as SVG.
std::string accuracySvg(const std::vector<AccuracyPoint>& points, const std::string& title);

// The scenes of the effects' (time, error) points: the nine of the tracer evaluation (room,
// gallery, atrium x vase, kettle, tripod), the gallery's bowl and metal bowl, and the window
// scene's bowl with its visitor; as hall:relic.
std::vector<std::string> effectScenes();

struct SceneSweep {
  AccuracyOptions options;
  AccuracySweep sweep;
};
// Each scene's effect points against its default tracer: the whole view's mse against ms per
// view, log-log, a segment from the default point to each variant, one colour per effect.
std::string effectsSvg(const std::vector<SceneSweep>& sweeps, const std::string& title);
// One Markdown row per scene and effect: whether the default's plan runs it, ms and mse with and
// without it, the ratio of the errors.
std::string effectsTable(const std::vector<SceneSweep>& sweeps);

// Every point as CSV, one row each: hall, relic, size, gt_spp, fg_pixels, method, knob, effect,
// ms, fg_mse, mse, pareto.
std::string accuracyCsv(const AccuracyOptions& options, const AccuracySweep& sweep);

}  // namespace holo::eval
