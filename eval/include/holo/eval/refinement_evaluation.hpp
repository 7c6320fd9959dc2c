// Progressive refinement while nothing moves (the frame renderer's ProgressiveRefinement), measured
// on a still scene at the live view size: a relic under a panorama seen by the four faces' default
// eyes, rendered frame after frame with nothing moving. Per frame n (1: the first, sample set 0
// alone) the error of the four views against the converged image (converged_sets sets), as the
// luminance RMS over the pixels where the rough interreflection shows divided by that light's own
// RMS there (the relic with its interreflection minus the relic without it); and the frame's time.
// The budget beside it, measured in turn in the same minutes: a refining frame, the frame when
// every eye moves (hit points and the static shading traced again) and the still frame without
// refinement (medians over timing_frames each).
// Units: milliseconds, ratios.
#pragma once

#include <string>
#include <vector>

namespace holo::eval {

struct RefinementEvaluationOptions {
  std::string relic = "metal-bowl";  // a built-in relic (relics::relicNames)
  std::string panorama;              // an HDR panorama file; empty: a synthetic sky with a bright window
  int view_size = 320;               // pixels per face view, as the live loop's
  int frames = 64;                   // frames of the curve
  int converged_sets = 256;          // sample sets of the converged image
  int timing_frames = 9;             // frames per median of the budget's frames
  // The live loop's tracer settings (pipeline::liveTracerSettings: one sample per pixel with edge
  // anti-aliasing, static reuse within 1 cm) with the interreflection on, which the loop leaves
  // off; false: the tracer's defaults (four samples per pixel), the evaluations'.
  bool live_loop = false;
  // The axis-aligned filter of the rough lobe (TracerSettings' evaluation knob); false: unfiltered
  // sums, the accumulation alone.
  bool axis_aligned_filter = true;
};

struct RefinementEvaluation {
  std::vector<double> error;     // per frame n = 1..frames, against the converged image
  std::vector<double> frame_ms;  // per frame, the renderer's frame (four views)
  double moved_ms = 0;           // median frame with every eye moved
  double reused_ms = 0;          // median still frame without refinement
  double refining_ms = 0;        // median refining frame
  std::size_t region_pixels = 0;
  double interreflected_rms = 0;  // luminance RMS of the interreflected light over the region
  std::string plan;               // the effect plan of a still frame
  // Frames within `seconds` at the refining frame rate, and the first frame whose error is at
  // most `bar` (0: none within the curve).
  int framesWithin(double seconds) const;
  int firstFrameBelow(double bar) const;
  // The frames from 1 to `last` (inclusive) each at most the one before.
  bool monotonicUpTo(int last) const;
};

// Throws InputError for an unknown relic or an unreadable panorama.
RefinementEvaluation evaluateRefinement(const RefinementEvaluationOptions& options);

// The curve as an SVG plot (frames against error, log-log) with the 10% bar and the frame 2 s gives.
std::string refinementPlotSvg(const RefinementEvaluation& evaluation, const std::string& title);

}  // namespace holo::eval
