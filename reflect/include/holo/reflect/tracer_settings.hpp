// The reflection tracer's settings (frame_renderer.hpp). TracerSettings holds the knobs the live
// product sets (the kiosk's degradation policy, the installation's frame loop, `run`);
// TracerEvaluationKnobs holds those that exist only to measure the tracer, against path-traced
// truth or against itself with a stage or a shortcut turned off, and that the live product leaves
// at their defaults. Per field: what it means, its unit and valid range (validate() throws
// InputError naming the field outside it), its default and why. The measurements behind the
// defaults are in docs/tracer.md.
// Units: metres, linear radiance, perceptual roughness in [0, 1] (a threshold above 1: never).
#pragma once

#include <optional>

#include "holo/core/plinth.hpp"
#include "holo/reflect/voxel_grid.hpp"

namespace holo::reflect {

// The largest number of interface events a transmitted path follows (refraction_depth).
inline constexpr int kMaxInternalDepth = 32;

// Departures from the live tracer, for measuring it; every default is the live tracer.
struct TracerEvaluationKnobs {
  // Pyramid levels added to every read's derived level (foregroundLevel), finite, within
  // +-kMaxPyramidLevels; default 0, the derived level. Checks the derivation against
  // path-traced truth.
  float level_bias = 0.0f;
  // Factor on the transmitted lobe's derived roughness (its IBL level and the walk's pyramid
  // levels), 0..4; default 1, the derived roughness. Checks the derivation against path-traced
  // truth.
  float transmitted_roughness_scale = 1.0f;
  // Refraction through transmissive relic materials; false: they are shaded as opaque. Default
  // true; false renders the opaque relic the glass is compared with.
  bool refraction_enabled = true;
  // The visitors seen through the glass (a walk per transmitted exit ray); false: refraction reads
  // the IBL only. Default true; false measures what the walk through the glass adds.
  bool refracted_foreground = true;
  // Below walk_per_pixel_roughness, a four-sample pixel walks each sub-sample only at the
  // reflected foreground's edges (a neighbour's pixel walk met it and this one's did not, or their
  // weights differ by more than 0.2) and elsewhere shares the pixel's walk; false: every sub-sample
  // walks (4x the rays). Default true, the same edges at a quarter of the rays; false is the
  // reference it is checked against.
  bool walk_edges_only = true;
  // Each hit point traces only its 2x2 pixel class's share of the rough interreflection's strata
  // and a 3x3 tent over the pixels of the same surface sums them all (static_shading.hpp); false:
  // every sample traces every stratum (side^2 rays). Default true, one ray per sample at side 4
  // with four samples; false is the reference it is checked against.
  bool rough_interreflection_interleaved = true;
  // The axis-aligned filter of the rough lobe's interleaved interreflection (axis_aligned_filter.hpp)
  // where the effect plan wants it; false: the 3x3 tent's sums alone. Default true; false measures
  // what the filter adds.
  bool axis_aligned_filter = true;
  // The relic's self-occlusion (relic_visibility.hpp) where the effect plan wants it; false: the
  // diffuse light is the unoccluded irradiance (the glTF occlusion texture the only visibility).
  // Default true; false measures what the visibility adds.
  bool self_occlusion = true;
  // A rough lobe's hall share is the prefiltered lobe scaled by the open samples' share of its
  // light (static_shading.hpp); false: by the open samples' count alone, the hall's light as if
  // spread evenly over the lobe. Default true; false measures what weighting by the light adds.
  bool lobe_visibility = true;
  // A rough lobe's strata are sampled, in a frame that accumulates none (sample set 0), at a point
  // within each stratum hashed from the pixel and sample (progressive_accumulation.hpp in
  // reflect/src), the same in every frame; false: at the strata's centres, a midpoint rule whose
  // lobe misses its tails (the metal bowl's inside 2-3% too bright at 4x4 strata,
  // docs/tracer/self_occlusion.md). Default true; false measures what the jitter removes.
  bool lobe_strata_jittered = true;
  // The interreflection of lobes at least kGlossyRoughnessLimit rough read from an object-space
  // cache per vertex and eye direction, shared by every view and frame while the light holds
  // (wide_lobe_cache.hpp in reflect/src); false: each sample traces its share of the strata, pooled,
  // filtered and refined as rougher-than-glossy lobes below that limit are. Default true: a view
  // that moves (a face following an eye) redoes its static shading every frame, and with the cache
  // that costs lookups instead of rays; false is the per-pixel estimate it is checked against.
  bool wide_lobe_cache = true;
  // The panorama's sun as a directional light with a shadow ray on the relic's diffuse surfaces
  // (sun_light.hpp in reflect/src) where the effect plan wants it (a sun found in the panorama);
  // false: the sun stays in the 9-coefficient diffuse light. Default true; false measures what the
  // sun light adds.
  bool sun_light = true;
  // The visitors' shadow and light on the relic's diffuse and widest lobes (visitor_light.hpp)
  // where the effect plan wants them; false: those are lit by the empty hall. Default true;
  // false measures what the visitors' light adds.
  bool visitor_light = true;
  // The transmissive relic's caustic on the plinth (caustic_tracer.hpp) where the effect plan
  // wants it; false: the plinth takes the relic's full shadow. Default true; false measures what
  // the caustic adds.
  bool plinth_caustic = true;
  // The relic's shadow on the plinth; false: the plinth takes the hall's unshadowed irradiance.
  // Default true; false measures what the shadow adds.
  bool plinth_shadow = true;
};

struct TracerSettings {
  // The foreground passes (voxel grid, pyramids, walk, composition); false: the static IBL only.
  // Default true; the kiosk turns it off to keep the frame rate.
  bool foreground_enabled = true;
  // Kawase pyramid levels per camera (l_max), each doubling the blur, 1..kMaxPyramidLevels;
  // default 7, the pyramid the figures of docs/tracer/voxel_walk.md are measured with.
  int pyramid_levels = 7;
  // Primary-ray sub-samples per pixel: 1 (the centre) or 4 (rotated grid, hit_points.hpp); default
  // 4, stable silhouettes on a still relic.
  int aa_samples = 4;
  // With aa_samples 1 only: 4 sub-samples at silhouette, crease and material-edge pixels
  // (AntiAliasing::Edges); default false, the centre alone.
  bool edge_aa = false;
  // Metres an eye may move (and its axis turn, that far at 0.5 m) before a view's cached hit
  // points and static shading are traced again, finite >= 0; default 0, reused only for the
  // identical camera so the image is exact.
  float static_reuse_distance = 0.0f;
  // Views whose eye moved beyond static_reuse_distance that trace their static passes again in one
  // frame, >= 0; the others show their cached passes a frame more, the longest waiting tracing
  // first (reflect/src/static_pass_schedule.hpp): the frame time stays that of one view traced
  // when several eyes move at once. Default 0: every such view traces in the frame its eye moved.
  int static_retraces_per_frame = 0;
  // Metres an eye may move before its view traces again whatever static_retraces_per_frame
  // leaves, finite, >= static_reuse_distance where static_retraces_per_frame > 0; default 0.
  float static_defer_distance = 0.0f;
  // Roughness from which a four-sample pixel walks once (the mean of its samples' rays) and
  // composes every sample with that foreground, >= 0; default 0.3: a lobe this rough reads a blur
  // wider than the sub-pixel offsets, below it the four walks anti-alias reflected edges.
  float walk_per_pixel_roughness = 0.3f;
  // One interreflection bounce: where a hit point's reflection meets the relic itself, it shows
  // that second point's static shading and foreground, scaled by the first point's specular
  // weight (static_shading.hpp); false: such pixels show the hall through the relic. Default true:
  // a concave relic (a vase's foot, the inside of its lip) mirrors itself, visitors included.
  bool relic_interreflection = true;
  // Roughness from which a reflected ray that meets no voxel marches to where it first passes
  // within two lobe sigmas of an occupied brick and reads the blurred pyramids there (the soft
  // halo a rough lobe shows beside a visitor), >= 0; default 0.2, where the halo is wider than a
  // voxel.
  float lobe_fallback_roughness = 0.2f;
  // Gaussians standing for the GGX lobe in each pyramid read (ggxLobeMixture), one read each,
  // 1..kMaxLobeComponents; default 2: one Gaussian misses GGX's heavy tail.
  int lobe_components = 2;
  // Roughness from which a hit point's foreground comes from RoughForegroundMap (the visitors
  // prefiltered around the relic) instead of the walk, >= 0; default 0.5: one walked ray and a
  // camera-space blur cannot stand for a lobe tens of degrees wide. The map is built per frame
  // only when an untextured relic material is this rough.
  float foreground_map_roughness = 0.5f;
  // RoughForegroundMap's width in texels (height width / 2), even, 8..1024; default 64, ~5.6
  // degrees a texel, fine for lobes that rough.
  int foreground_map_width = 64;
  // The interreflection of materials read from the rough map, a side of strata: > 1, their GGX
  // lobe sampled at the centres of side x side strata of its visible normals (even, 2..8), one
  // relic ray each, the share that meets the relic seeing the second points' static shading; 1:
  // the mirror ray alone, all or nothing (stripes where the truth is smooth). Default 4, one ray
  // per sample with four samples and interleaving.
  int rough_interreflection_grid = 4;
  // Roughness from which every material's interreflection traces the lobe's strata (as above)
  // instead of the mirror ray, >= 0 (> 1: only the materials read from the rough map); default
  // 0.3: a lobe this wide shows a soft glow of the relic's other parts, where the mirror ray
  // would show a sharp image of them.
  float rough_interreflection_roughness = 0.3f;
  // Mirror bounces a lobe stratum's second point follows over the relic, 1..8: each point met
  // adds its static shading and passes on what its mirror ray meets, the last one's prefiltered
  // hall read as if its lobe were open. Default 3: with 1, the third point's unoccluded lobe
  // leaves the metal bowl's inside 3-4% too bright (its light of three bounces and more 30-45%),
  // with 3 within 1.5% (docs/tracer/self_occlusion.md); a ray more per point that meets the relic.
  int rough_interreflection_mirror_bounces = 3;
  // Sample sets of the rough interreflection a still view accumulates, a set a frame
  // (progressive_accumulation.hpp in reflect/src; the plan's ProgressiveRefinement), 1..4096; 1:
  // off, every frame shows set 0 (lobe_strata_jittered). Default 64: the metal bowl's error
  // against the converged image is then below 3% of its interreflected light
  // (docs/tracer/progressive_refinement.md); later frames cost nothing.
  int refinement_sets = 64;
  // Rays per vertex and side of the relic's visibility (relic_visibility.hpp), built when the
  // renderer is built, for a relic that can shadow its own diffuse light: a square number 4..256;
  // default 256: the Lambert bowl's per-pixel error falls with more strata (2.2x lower than the
  // unoccluded light's at 64, 2.9x at 256; docs/tracer/self_occlusion.md).
  int self_occlusion_rays = 256;
  // Diffuse interreflection bounces folded into the visibility's transfer, 0..8; default 4: the
  // Lambert bowl's inside loses 3% of its light with 2 (docs/tracer/self_occlusion.md).
  int self_occlusion_bounces = 4;
  // A relic whose vertices are all less occluded than this share of their cosine-weighted
  // hemisphere gets no visibility (the plan leaves it off), [0, 1]; default 1/255: below one
  // sRGB code of a white surface.
  float self_occlusion_min = 1.0f / 255.0f;
  // sRGB codes a plan entry's estimated largest change of the displayed relic must reach for the
  // plan to run it, finite >= 0 (0: wherever it can change anything). SelfOcclusion's estimate:
  // RelicVisibility::largestDisplayedChange at each panorama's first frame; VisitorLight's:
  // VisitorLight::largestRadianceChange every frame; AxisAlignedFilter's and
  // ProgressiveRefinement's: the rough lobe's Monte Carlo spread (lobe_spread.hpp in reflect/src).
  // Default 1: a change below one code cannot be seen.
  float effect_min_codes = 1.0f;
  // Metres between the relic's box and the foreground's within which the visitors' shadow and
  // light on the relic's diffuse and widest lobes are computed (VisitorLight), finite >= 0;
  // default 1.5: a body there (about 0.5 x 1.7 m) hides about a fifth of a steradian, tenths of
  // a window's light; farther, the grid (2 m round the axis) holds little of it.
  float visitor_light_distance = 1.5f;
  // The visitors' light's probe maps, width in texels (height width / 2), even, 8..1024; default
  // 64, ~5.6 degrees a texel, finer than the clamped cosine's second band resolves.
  int visitor_light_map_width = 64;
  // Metres a reflected ray may travel through the grid, finite > 0; default 3, the default grid's
  // corners are about 3 m from the relic.
  float max_reflection_distance = 3.0f;
  // Metres a reflected ray starts along the normal, against self-intersection, 0..0.1; default
  // 1 mm, far above float error at the relic's scale, far below its features (the tripod's 8 mm
  // wall).
  float ray_offset = 1e-3f;
  // Exposure of the tone map, finite; <= 0: automatic per view (tone_map.hpp's autoExposure).
  // Default 0; the frame loop fixes it at its first frame's automatic choice, so the relic does
  // not pump as visitors come and go.
  float exposure = 0.0f;
  // Interface events a transmitted path follows through the relic (refraction_pass.hpp), 0 or
  // 1..kMaxInternalDepth; default 0, measured on the relic when the renderer is built (the
  // smallest depth that leaves less than refraction_residual of the transmitted light inside).
  int refraction_depth = 0;
  // Share of the transmitted light the measured depth may leave to the IBL, in (0, 1); default
  // 0.01, 1% of a glass pixel's transmitted light, under 1 sRGB code at mid-grey.
  float refraction_residual = 0.01f;
  // Pixels between the transmitted paths' anchors (refraction_pass.hpp), 1..4; 1: every sample
  // traces; s > 1: anchors every s pixels (every 2s-th traces, the others blend those where they
  // agree), the samples between blending the anchors where these agree, tracing elsewhere.
  // Default 2; docs/tracer/glass.md has its error and time against the other strides.
  int refraction_stride = 2;
  // Rays a transmitted path may spend following the light reflected inside at a partial exit
  // (refraction_pass.hpp), 0..64; 0: all of it summed as between parallel walls, which sends a
  // cut crystal's light back in large facet images. Default 8; docs/tracer/glass.md has its error and
  // time against other budgets.
  int refraction_branch_rays = 8;
  // Share of the light entering below which the light reflected inside at a partial exit is summed
  // as between parallel walls instead of followed, [0, 1]; default 0.1: a diamond's exits near its
  // critical angle are followed, ordinary glass (F ~ 0.04) keeps the sum and its visitors.
  float refraction_branch_weight = 0.1f;
  // Luminance ratio of the transmitted light among a four-sample pixel's samples above which each
  // takes the mean of 16 paths across its quarter of the pixel (refraction_pass.hpp), 0 or >= 1;
  // 0: off. Default 32: a lamp seen through a crystal's facets by some of the samples and not the
  // others, while a glass wall's changing thickness stays below it.
  float refraction_supersample_contrast = 32.0f;
  // The voxel grid the walk traverses (voxel_grid.hpp).
  VoxelGridSettings grid;
  // A virtual plinth under the relic (core/plinth.hpp), drawn in every view, lit by the hall and
  // shadowed by the relic; absent: none. Its top's light map has plinth_map_resolution texels a
  // side (8..1024) with plinth_shadow_rays rays each (1..4096, squared to strata); a transmissive
  // relic's caustic on it takes caustic_photons photons (1..1e9) binned on caustic_resolution
  // cells a side (8..2048).
  std::optional<PlinthSettings> plinth;
  int plinth_map_resolution = 64;
  int plinth_shadow_rays = 64;
  std::uint64_t caustic_photons = 1u << 20;
  int caustic_resolution = 128;
  // The departures for measuring the tracer; the live product leaves them at their defaults.
  TracerEvaluationKnobs evaluation;
  // Throws InputError naming the field (an evaluation knob by its own name).
  void validate() const;
};

}  // namespace holo::reflect
