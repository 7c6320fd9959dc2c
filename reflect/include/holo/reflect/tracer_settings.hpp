// The reflection tracer's settings (frame_renderer.hpp).
#pragma once

#include "holo/reflect/voxel_grid.hpp"

namespace holo::reflect {

// The reflection tracer's settings. Per field: what it means, its unit and valid range
// (validate() throws InputError naming the field outside it), the default and why. The
// measurements behind the defaults are in docs/tracer.md.
struct TracerSettings {
  // The foreground passes (voxel grid, pyramids, walk, composition); false: the static IBL only.
  bool foreground_enabled = true;
  // Kawase pyramid levels per camera (l_max), 1..kMaxPyramidLevels, each doubling the blur; 7:
  // the figures of docs/tracer.md.
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

}  // namespace holo::reflect
