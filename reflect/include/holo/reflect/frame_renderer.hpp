// The efficient reflection tracer's frame renderer (paper steps 3-5): per frame it bins the
// foreground cloud into the voxel grid and builds each camera's Kawase pyramids, then per face
// view traces hit points on the relic, shades the static reflection psi_s from the prefiltered
// IBL (one bounce further where the mirror ray meets the relic itself), walks each reflected ray
// through the voxel grid for the foreground radiance psi_d and weight w (the camera that saw the
// voxel, read at the pyramid levels of the hit's GGX lobe and the ray's travel distance; the
// roughest materials read the visitors prefiltered around the relic instead), composes
// psi_f = psi_d w + psi_s (1 - w) in HDR (specular part; the diffuse irradiance is added to
// both), and tone-maps to sRGB. Which passes run comes from the effect plan (effect_plan.hpp);
// every pass is timed. The passes live in reflect/src: static_shading, foreground_walk (with its
// camera choice and near-miss march), compose_pass, and tone_map.hpp's toneMapCovered.
//
// The relic and the hall do not move, only the eyes: per view slot (the index in `views`) the
// renderer keeps the hit points, their static shading and the static image (psi_s + diffuse, and
// its tone-mapped form when the exposure is fixed), and reuses them while that view's camera stays
// within static_reuse_distance of the one they were traced from (the result is then rendered from
// the cached camera). A frame then costs only the foreground: the walk over the cached hit
// points and the composition of the pixels some foreground reached, written over a copy of the
// static image.
// Units: metres, linear radiance; images CV_32FC3 linear BGR (HDR) and CV_8UC3 sRGB BGR.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/reflect/effect_plan.hpp"
#include "holo/reflect/foreground_pyramid.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/rough_foreground_map.hpp"
#include "holo/reflect/voxel_grid.hpp"
#include "holo/reflect/voxel_walk.hpp"

namespace holo::reflect {

struct TracerSettings {
  bool foreground_enabled = true;
  int pyramid_levels = 7;  // l_max, 1..kMaxPyramidLevels
  int aa_samples = 4;      // sub-samples per pixel: 1 or 4
  bool edge_aa = false;    // with 1 sample: 4 at silhouette and crease pixels (hit_points.hpp)
  // Metres an eye may move before a view's cached hit points and static shading are traced
  // again; 0 reuses them only for the identical camera (no error at all).
  float static_reuse_distance = 0.0f;
  // One walk per pixel where the relic is at least this rough: a pixel with four sub-samples walks
  // the mean of their reflected rays once and composes every sub-sample with that foreground (each
  // keeps its own static shading and coverage). A rough lobe's footprint spans many sub-pixel
  // offsets, so the four walks would read nearly the same blurred texel; on a mirror the four
  // walks anti-alias the reflected visitors' edges (one walk per pixel there raised gallery x
  // vase's fg_mse 1.75x, docs/tracer.md). > 1: every sub-sample walks.
  float walk_per_pixel_roughness = 0.3f;
  // Below that roughness, walk each sub-sample only at the reflected foreground's edges: every
  // pixel first walks its mean ray once; where a neighbour's walk met the foreground and this
  // one's did not (or their weights differ by more than 0.2) the four sub-samples walk, elsewhere
  // they share the pixel's walk. false: every sub-sample walks (4x the rays).
  bool walk_edges_only = true;
  // One interreflection bounce: where a hit point's mirror ray meets the relic itself (a vase's
  // foot under its bulge, the inside of its lip), its reflection is that second point's (static
  // shading, and the foreground walk from there), scaled by the first point's specular weight;
  // without it such pixels show the hall straight through the relic. Traced with the static
  // passes (one extra ray per hit point, cached with them). Where a visitor is seen over the
  // relic's own surface this was most of a mirror-like vase's fg_mse (docs/tracer.md).
  bool relic_interreflection = true;
  // Rough lobes that miss: a reflected ray whose mirror direction meets no voxel may still pass
  // within its lobe's footprint of a visitor, and the truth then shows a soft halo where a hit/miss
  // decision would cut a hard edge. From this roughness on, such a ray marches the brick
  // distances to the first point within two lobe sigmas of an occupied brick and reads the
  // blurred pyramids there (the camera looking most along the ray): the blurred mask gives the
  // partial weight. > 1: never.
  float lobe_fallback_roughness = 0.2f;
  // Gaussians standing for the GGX lobe in each pyramid read (ggxLobeMixture), one read each: 1
  // reads the level of the lobe's Beckmann-equivalent sigma, which misses GGX's heavy tail (the
  // reflected visitor came out too sharp and too saturated on the kettle, 0.35); 2 cut the
  // kettles' fg_mse 2.9-3x against path-traced truth, more changed nothing (docs/tracer.md).
  int lobe_components = 2;
  // From this roughness on a hit point's foreground comes from RoughForegroundMap (the visitors
  // prefiltered around the relic with its lobe, rough_foreground_map.hpp) instead of the walk:
  // one walked ray and a camera-space blur cannot stand for a lobe tens of degrees wide (the
  // tripod, 0.6, showed hard-edged patches in one camera's colours). Built per frame only when a
  // relic material is this rough (not textured). > 1: never.
  float foreground_map_roughness = 0.5f;
  int foreground_map_width = 64;  // texels around; the map is width x width / 2
  // The interreflection of those rough materials: > 1, sampled over their GGX lobe at the
  // centres of side x side strata of its visible normals (even sides), one relic ray each; the
  // share that meets the relic sees its second points, the rest the hall. 1: the mirror ray
  // alone, all or nothing (the tripod's bowl showed stripes of the hall where the truth is
  // smooth). Interleaved (the default), each hit point traces only its share of the strata:
  // every other stratum per 2x2 pixel class, dealt to the pixel's samples (1 ray per sample at
  // side 4 with 4 samples, 4 with 1 sample), and a 3x3 tent over the pixels of the same surface
  // sums them all; otherwise every sample traces every stratum (side^2 rays). Traced with the
  // static passes, again whenever an eye moves (docs/tracer.md).
  int rough_interreflection_grid = 4;
  bool rough_interreflection_interleaved = true;
  // Added to the derived pyramid level (foregroundLevel) of every read, for checking the
  // derivation against path-traced truth (bench accuracy); 0 in use.
  float level_bias = 0.0f;
  float max_reflection_distance = 3.0f;  // metres a reflected ray may travel through the grid
  float ray_offset = 1e-3f;              // metres along the normal, against self-intersection
  float exposure = 0.0f;                 // <= 0: automatic (tone_map.hpp's autoExposure)
  VoxelGridSettings grid;
  // Throws InputError naming the field.
  void validate() const;
};

// One foreground camera of this frame: its model and the filtered colour and mask it saw.
struct ForegroundCameraImage {
  CameraModel camera;
  cv::Mat colour_bgr;  // CV_32FC3 linear; read only inside the mask's non-zero bounding box
  cv::Mat mask;        // CV_32FC1 [0, 1] or CV_8UC1
};

struct PassTiming {
  Pass pass;
  double ms = 0.0;
};

struct ViewImages {
  cv::Mat hdr;       // psi_f, CV_32FC3 linear BGR; 0 where nothing is seen
  cv::Mat weight;    // mean foreground weight w per pixel, CV_32FC1 [0, 1]
  cv::Mat coverage;  // relic coverage per pixel, CV_32FC1 [0, 1]
  cv::Mat display;   // CV_8UC3 sRGB BGR
  float exposure = 1.0f;
  std::vector<PassTiming> timings;  // this view's passes
  std::uint64_t walked_rays = 0, foreground_hits = 0;
  CameraModel camera;               // the camera the images are from (the cached one when reused)
  bool static_reused = false;       // hit points and static shading came from the cache
  std::size_t refined_pixels = 0;   // pixels with 4 sub-samples
  std::size_t composed_pixels = 0;  // pixels some foreground reached, composed this frame
};

struct FrameResult {
  EffectPlan plan;
  std::vector<PassTiming> frame_timings;  // per-frame passes (voxel grid, pyramids)
  std::vector<ViewImages> views;
};

class FrameRenderer {
 public:
  // The scene and IBL must outlive the renderer. Throws InputError on invalid settings.
  FrameRenderer(const RenderScene& scene, const PrefilteredIbl& ibl, TracerSettings settings = {});
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  EffectPlan plan(const depthfilter::ForegroundCloud& cloud,
                  const std::vector<ForegroundCameraImage>& cameras) const;
  // Renders every view of one frame. A point whose camera index has no image is ignored.
  FrameResult render(const depthfilter::ForegroundCloud& cloud,
                     const std::vector<ForegroundCameraImage>& cameras,
                     const std::vector<CameraModel>& views);

  const VoxelGrid& grid() const { return grid_; }
  const TracerSettings& settings() const { return settings_; }
  // Fixes the exposure (> 0) or makes it automatic (<= 0) from the next frame on.
  void setExposure(float exposure);

 private:
  struct ViewCache;
  ViewImages renderView(const EffectPlan& plan, const std::vector<ForegroundCameraImage>& cameras,
                        const CameraModel& view, ViewCache& cache) const;

  const RenderScene& scene_;
  const PrefilteredIbl& ibl_;
  TracerSettings settings_;
  bool relic_glossy_ = false;
  Bounds3 relic_bounds_;  // of the static relic, for culling primary rays
  VoxelGrid grid_;
  std::vector<ForegroundPyramid> pyramids_;
  // For the relic materials at least foreground_map_roughness rough; null when there is none.
  std::unique_ptr<RoughForegroundMap> rough_map_;
  std::vector<std::unique_ptr<ViewCache>> caches_;  // per view slot
};

}  // namespace holo::reflect
