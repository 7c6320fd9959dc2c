// Progressive refinement while nothing moves (Kán's thesis, Sec. 4.4, Eq. 4.12) of the live
// renderer's one Monte Carlo part, the rough interreflection (static_shading.hpp): a material at
// least rough_interreflection_roughness rough traces its GGX lobe at strata that each sample of a
// pixel takes a share of, pooled over a 3x3 tent. A moving scene shows sample set 0, a point
// within each stratum hashed from the pixel and sample, the same in every frame (the thesis'
// preview mode: the same random parameters each frame keep it temporally coherent; the strata's
// centres would be a midpoint rule that misses the lobe's tails). A still view takes sample set n = 1, 2, ...
// in its following frames, each a new offset within every stratum, and accumulates: the per-pixel sums of the
// lobe samples over the sets (LobeBounce) grow by one set a frame, and the pixel shows their pooled ratio,
// which is Eq. 4.12's running mean L_acc = ((n - 1) L_acc + L_o) / n of the interreflected light (exactly so
// where every set has the same count of samples above the surface).
//
// Still: the view's static shading was reused (FrameRenderer: the same camera, or within
// static_reuse_distance; a moved eye, a relic turn or new lighting traces the view again, which
// restarts at set 0) and the foreground voxel grid holds what it held in the view's previous frame
// (foregroundSignature). A changed foreground resets the view to set 0 in that frame.
//
// Cost: a refining frame shades each rough sample of the view again (one lobe ray, and the
// second point's mirror rays where it reflects, up to rough_interreflection_mirror_bounces, per
// sample; no hit points), pools and composes
// those pixels: at most the static pass's work on them, which a moved eye's frame does anyway. A
// reset costs the same once; a view that stays reset (the foreground keeps changing) or has
// accumulated TracerSettings::refinement_sets sets does no work at all.
// What it shows: the view's image at set 0 is kept for its rough pixels, and once kMeasuredSets
// sets are in, the largest change of a displayed code between them is the gate's measure
// (lobe_effect_gate.hpp): the plan leaves a view's refinement off where it is below a code.
// Sample sets: lobe_sample_sets.hpp.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "axis_aligned_filter.hpp"
#include "holo/core/camera_model.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/voxel_grid.hpp"
#include "static_shading.hpp"

namespace holo::reflect {

// What the foreground voxel grid holds (its occupied voxels' kept points: camera, pixel, radiance,
// weight), independent of the order they were binned in; equal for two grids holding the same.
std::uint64_t foregroundSignature(const VoxelGrid& grid);

// What a view's accumulation did this frame.
struct RefinementStep {
  std::uint32_t sets = 0;      // sample sets the view's image now holds (1: set 0 alone)
  std::uint64_t samples = 0;   // samples shaded again this frame (0: nothing to do)
  bool reset = false;          // the foreground changed: back to set 0
  bool image_changed = false;  // hdr (and the shading) were written this frame
  FilterCounts filtered;       // the axis-aligned filter's, where it ran
};

// One view's accumulation, kept with its static shading (FrameRenderer's view cache).
class ProgressiveAccumulation {
 public:
  // The sets after which what the refinement changed is measured (largestChange): with n sets the
  // change from set 0 has sqrt(1 - 1/n) of the converged change's spread, 0.94 at 8.
  static constexpr std::uint32_t kMeasuredSets = 8;

  // The view's static pass has just shaded set 0: `bounces` (StaticShading::shade's) holds its
  // sums and `hdr` its image; its rough pixels are the ones refined from now on.
  void restart(const std::vector<PixelBounce>& bounces, const cv::Mat& hdr, std::uint64_t foreground);
  // The view's static pass has shaded set 0 without refinement: nothing to refine until the next
  // restart (advance does no work).
  void stop();
  // A frame whose static shading was reused: with the same foreground, the next sample set added
  // (until max_sets); with another, back to set 0. shading, walk_rays and bounces are the view's,
  // after shade() and restart(); hdr, the view's static image, is replaced by a new image when
  // written (an image handed out before is never written). `filter` (may be null): the static
  // pass's axis-aligned filter, applied to the accumulated sums as to set 0's.
  RefinementStep advance(const StaticShading& shading_pass, const HitPointBuffer& hits,
                         const CameraModel& view, std::uint64_t foreground, std::uint32_t max_sets,
                         std::vector<SplitSumShading>& shading, std::vector<WalkRay>& walk_rays,
                         std::vector<PixelBounce>& bounces, cv::Mat& hdr,
                         const AxisAlignedFilter* filter = nullptr);
  std::uint32_t sets() const { return sets_; }
  // The largest change of a displayed sRGB code (unrounded, any channel, at `exposure`) between
  // set 0's image and `hdr` (the view's accumulated one) over the refined pixels.
  float largestChange(const cv::Mat& hdr, float exposure) const;

 private:
  std::vector<std::uint32_t> pixels_;  // the view's pixels with rough lobe samples
  std::vector<vec3> first_;            // their radiance (linear RGB) at set 0
  std::uint32_t sets_ = 0;
  std::uint64_t foreground_ = 0;
};

}  // namespace holo::reflect
