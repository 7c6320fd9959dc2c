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

// The reflection tracer's settings. Per field: what it means, its unit and valid range
// (validate() throws InputError naming the field outside it), the default and why. The
// measurements behind the defaults are in docs/tracer/ (one page per component).
struct TracerSettings {
  // The foreground passes (voxel grid, pyramids, walk, composition); false: the static IBL only.
  bool foreground_enabled = true;
  // Kawase pyramid levels per camera (l_max), 1..kMaxPyramidLevels, each doubling the blur; 7:
  // the figures of docs/tracer/evaluation.md.
  int pyramid_levels = 7;
  // Primary-ray sub-samples per pixel, 1 (the centre) or 4 (rotated grid, hit_points.hpp); 4:
  // stable silhouettes on a still relic.
  int aa_samples = 4;
  // With aa_samples 1 only: 4 sub-samples at silhouette, crease and material-edge pixels
  // (AntiAliasing::Edges); false: the centre alone.
  bool edge_aa = false;
  // Metres an eye may move (and its axis turn, that far at 0.5 m) before a view's cached hit
  // points and static shading are traced again, >= 0; 0: reused only for the identical camera,
  // so the image is exact.
  float static_reuse_distance = 0.0f;
  // Roughness from which a four-sample pixel walks once (the mean of its samples' rays) and
  // composes every sample with that foreground, >= 0 (> 1: never); 0.3: a lobe this rough reads a
  // blur wider than the sub-pixel offsets, below it the four walks anti-alias reflected edges.
  float walk_per_pixel_roughness = 0.3f;
  // Below walk_per_pixel_roughness, walk each sub-sample only at the reflected foreground's edges
  // (a neighbour's pixel walk met it and this one's did not, or their weights differ by more
  // than 0.2), elsewhere share the pixel's walk; false: every sub-sample walks (4x the rays).
  // true: the same edges at a quarter of the rays.
  bool walk_edges_only = true;
  // One interreflection bounce: where a hit point's reflection meets the relic itself, it shows
  // that second point's static shading and foreground, scaled by the first point's specular
  // weight (static_shading.hpp); false: such pixels show the hall through the relic. true: a
  // concave relic (a vase's foot, the inside of its lip) mirrors itself, visitors included.
  bool relic_interreflection = true;
  // Roughness from which a reflected ray that meets no voxel marches to where it first passes
  // within two lobe sigmas of an occupied brick and reads the blurred pyramids there (the soft
  // halo a rough lobe shows beside a visitor), >= 0 (> 1: never); 0.2: where the halo is wider
  // than a voxel.
  float lobe_fallback_roughness = 0.2f;
  // Gaussians standing for the GGX lobe in each pyramid read (ggxLobeMixture), one read each,
  // 1..kMaxLobeComponents; 2: one Gaussian misses GGX's heavy tail, more than 2 changed nothing.
  int lobe_components = 2;
  // Roughness from which a hit point's foreground comes from RoughForegroundMap (the visitors
  // prefiltered around the relic) instead of the walk, >= 0 (> 1: never); 0.5: one walked ray
  // and a camera-space blur cannot stand for a lobe tens of degrees wide. The map is built per
  // frame only when an untextured relic material is this rough.
  float foreground_map_roughness = 0.5f;
  // RoughForegroundMap's width in texels (height width / 2), even, 8..1024; 64: ~5.6 degrees a
  // texel, fine for lobes that rough.
  int foreground_map_width = 64;
  // The interreflection of materials read from the rough map: > 1, their GGX lobe sampled at the
  // centres of side x side strata of its visible normals (even side 2..8), one relic ray each,
  // the share that meets the relic seeing the second points' static shading; 1: the mirror ray
  // alone, all or nothing (stripes where the truth is smooth). 4 with interleaving: 1 ray per
  // sample with 4 samples.
  int rough_interreflection_grid = 4;
  // Each hit point traces only its 2x2 pixel class's share of those strata and a 3x3 tent over
  // the pixels of the same surface sums them all (static_shading.hpp); false: every sample
  // traces every stratum (side^2 rays).
  bool rough_interreflection_interleaved = true;
  // Added to every pyramid read's derived level (foregroundLevel), within +-kMaxPyramidLevels,
  // for checking the derivation against path-traced truth (bench accuracy); 0 in use.
  float level_bias = 0.0f;
  // Metres a reflected ray may travel through the grid, finite > 0; 3: the default grid's
  // corners are about 3 m from the relic.
  float max_reflection_distance = 3.0f;
  // Metres a reflected ray starts along the normal, against self-intersection, 0..0.1; 1 mm:
  // far above float error at the relic's scale, far below its features (the tripod's 8 mm wall).
  float ray_offset = 1e-3f;
  // Exposure of the tone map, finite; <= 0: automatic per view (tone_map.hpp's autoExposure).
  float exposure = 0.0f;
  // Interface events a transmitted path follows through the relic (refraction_pass.hpp), 0 or
  // 1..32; 0: measured on the relic when the renderer is built (the smallest depth that leaves less
  // than refraction_residual of the transmitted light inside).
  int refraction_depth = 0;
  // Refraction through transmissive relic materials; false: they are shaded as opaque (the
  // renderer before the refraction pass, for comparisons).
  bool refraction_enabled = true;
  // The visitors seen through the glass (a walk per transmitted exit ray); false: refraction reads
  // the IBL only (the comparison the bar names).
  bool refracted_foreground = true;
  // Share of the transmitted light the measured depth may leave to the IBL, (0, 1); 0.01: 1% of
  // a glass pixel's transmitted light, under 1 sRGB code at mid-grey.
  float refraction_residual = 0.01f;
  // Scales the transmitted lobe's derived roughness (the IBL level and the walk's pyramid
  // levels), 0..4; 1 in use, for checking the derivation against path-traced truth.
  float transmitted_roughness_scale = 1.0f;
  // Pixels between the transmitted paths' anchors (refraction_pass.hpp), 1..4; 1: every sample
  // traces; s > 1: anchors every s pixels (every 2s-th traces, the others blend those where they
  // agree), the samples between blending the anchors where these agree, tracing elsewhere.
  int refraction_stride = 2;
  // Rays a transmitted path may spend following the light reflected inside at a partial exit
  // (refraction_pass.hpp), 0..64; 0: all of it summed as between parallel walls.
  int refraction_branch_rays = 8;
  // Share of the light entering below which the light reflected inside at a partial exit is summed
  // as between parallel walls instead of followed, [0, 1]; 0.1: a diamond's exits near its critical
  // angle are followed, ordinary glass (F ~ 0.04) keeps the sum and its visitors.
  float refraction_branch_weight = 0.1f;
  // Luminance ratio of the transmitted light among a four-sample pixel's samples above which each
  // takes the mean of 16 paths across its quarter of the pixel (refraction_pass.hpp), 0 or >= 1;
  // 0: off. 32: a lamp seen through a crystal's facets by some of the samples, not the others
  // (a glass wall's changing thickness stays below it: at 16 the glass vase's frame casts 1.7
  // times the refraction rays, at 32 as many as without).
  float refraction_supersample_contrast = 32.0f;
  // The voxel grid the walk traverses (voxel_grid.hpp).
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
  // Material layers (refraction_pass.hpp): Embree rays of the transmitted paths and the samples
  // that traced one (when the static shading was traced this frame), the transmitted exit rays
  // walked for the visitors (every frame with foreground), the clearcoated samples.
  std::uint64_t refraction_rays = 0, refracted_samples = 0, capped_paths = 0, refracted_walks = 0;
  std::uint64_t supersampled_samples = 0;  // samples whose transmitted light is a mean of paths
  std::uint64_t coated_samples = 0;
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
  bool relic_transmissive_ = false, relic_clearcoat_ = false;
  int internal_depth_ = 0;  // with a transmissive relic: settings' or measured
  float internal_residual_ = 0.0f;
  Bounds3 relic_bounds_;  // of the static relic, for culling primary rays
  VoxelGrid grid_;
  std::vector<ForegroundPyramid> pyramids_;
  // For the relic materials at least foreground_map_roughness rough; null when there is none.
  std::unique_ptr<RoughForegroundMap> rough_map_;
  std::vector<std::unique_ptr<ViewCache>> caches_;  // per view slot
};

}  // namespace holo::reflect
