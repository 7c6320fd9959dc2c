// What the frame renderer returns for a frame: per face view its images and counters, per frame
// the effect plan and the timings of the passes run once for all views.
// Units: linear radiance; images CV_32FC3 linear BGR (HDR) and CV_8UC3 sRGB BGR.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"
#include "holo/reflect/effect_plan.hpp"
#include "holo/reflect/pass_timing.hpp"

namespace holo::reflect {

// What one view's passes did this frame, for the statistics.
struct ViewCounters {
  std::uint64_t walked_rays = 0, foreground_hits = 0;  // reflected rays walked; those that met the foreground
  bool static_reused = false;                          // hit points and static shading came from the cache
  // Among those: its eye had moved beyond the reuse distance and its trace was left to a later
  // frame (TracerSettings::static_retraces_per_frame).
  bool static_deferred = false;
  std::size_t refined_pixels = 0;   // pixels with 4 sub-samples
  std::size_t composed_pixels = 0;  // pixels some foreground reached, composed this frame
  // Material layers (refraction_pass.hpp): Embree rays of the transmitted paths, the samples that
  // traced one, the paths that reached the depth cap, the supersampled and the clearcoated samples
  // (0 when the static shading was reused); the transmitted exit rays walked for the visitors
  // (every frame with foreground).
  std::uint64_t refraction_rays = 0, refracted_samples = 0, capped_paths = 0, refracted_walks = 0;
  std::uint64_t supersampled_samples = 0;  // samples whose transmitted light is a mean of paths
  std::uint64_t coated_samples = 0;
  // Samples whose diffuse light the relic's visibility occluded (SelfOcclusion; 0 when the static
  // shading was reused or the plan left it off).
  std::uint64_t occluded_samples = 0;
  // ProgressiveRefinement: the rough interreflection's sample sets the image holds (1: set 0, a
  // moving scene's; 0 without the pass), the samples shaded again this frame, and whether a
  // changed foreground reset the view to set 0 this frame.
  std::uint32_t accumulated_sets = 0;
  std::uint64_t refinement_samples = 0;
  bool refinement_reset = false;
  // Samples whose light the visitors changed (VisitorLight; 0 when the plan left it off).
  std::uint64_t visitor_lit_samples = 0;
  std::uint64_t plinth_pixels = 0;  // Plinth: pixels where the plinth is seen
  // Pixels whose rough-lobe interreflection the axis-aligned filter smoothed, and the weights it
  // took (AxisAlignedFilter; 0 when the static shading was reused or the plan left it off).
  std::uint64_t filtered_pixels = 0, filter_taps = 0;
  // The largest change of a displayed sRGB code (unrounded) the filter made in this view's static
  // pass (0 when it did not run there): what the plan's gate weighs it with.
  float filter_codes = 0.0f;
  // The largest change of a displayed sRGB code (unrounded) between the view's set 0 and its
  // accumulation, measured in the frame it reached ProgressiveAccumulation::kMeasuredSets sets (0
  // in other frames): what the plan's gate weighs the refinement with.
  float refinement_codes = 0.0f;
  // Samples shaded, those that cast an interreflection ray and the rays they cast (0 when the
  // static shading was reused; no ray on a convex relic: the plan leaves the effect off).
  std::uint64_t shaded_samples = 0, interreflected_samples = 0, interreflection_rays = 0;
  std::uint64_t sun_rays = 0;  // the sun light's shadow rays (the static pass's; 0 with it off)
};

// One view's images, with its counters.
struct ViewImages : ViewCounters {
  cv::Mat hdr;       // psi_f, CV_32FC3 linear BGR; 0 where nothing is seen
  cv::Mat weight;    // mean foreground weight w per pixel, CV_32FC1 [0, 1]
  cv::Mat coverage;  // relic coverage per pixel, CV_32FC1 [0, 1]
  cv::Mat display;   // CV_8UC3 sRGB BGR
  float exposure = 1.0f;
  std::vector<PassTiming> timings;  // this view's passes
  CameraModel camera;               // the camera the images are from (the cached one when reused)
};

struct FrameResult {
  EffectPlan plan;
  std::vector<PassTiming> frame_timings;  // per-frame passes (voxel grid, pyramids)
  std::vector<ViewImages> views;
  // VisitorLight's build this frame: voxel splats and covered texels over its probes (0 without it).
  std::uint64_t visitor_light_splats = 0, visitor_light_texels = 0;
  // Plinth and Caustics, on the frames that relight the plinth (its first, a new panorama or relic
  // turn): the shadow rays of its top and the caustic's photons launched and landed on it.
  std::uint64_t plinth_shadow_rays = 0, caustic_photons_traced = 0, caustic_photons_stored = 0;
};

}  // namespace holo::reflect
