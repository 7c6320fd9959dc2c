// The frame renderer's material layers (internal): refraction through transmissive relic
// materials (KHR_materials_transmission, _volume, _ior) and the clearcoat's second specular lobe
// (KHR_materials_clearcoat), on top of the static shading of each hit point.
//
// Refraction. At a hit point of a transmissive material the light splits by the exact
// unpolarised Fresnel reflectance F of its IOR: F goes to the reflection (the specular scale the
// composition already blends with the visitors), (1 - F) (1 - metallic) transmission base_colour
// enters the relic. The transmitted path is traced with Embree through the relic, one ray per
// interface event (entering, leaving, a total internal reflection), up to `internal_depth` events:
//  * entering from outside: Snell refraction, F of it reflected back out, the rest tinted by
//    base_colour (glTF's specular BTDF);
//  * leaving: where F = 1 (total internal reflection) the path reflects and goes on. Otherwise the
//    refracted (1 - F) leaves, and the light that partly reflects inside is followed where it is
//    at least TracerSettings::refraction_branch_weight of the light entering and the path's
//    refraction_branch_rays last: it bounces on inside, each of its exits reading the
//    prefiltered IBL along its refracted ray into `resolved` (a crystal's facets send it out in
//    many directions). Where they stop it, it is summed in closed form as between two parallel
//    walls with the same F and the last segment's absorption a: (1 - F) / (1 - F^2 a^2) leaves
//    along the refracted ray, F a (1 - F) / (1 - F^2 a^2) leaves back towards the side it came
//    from. Exact for a slab; everywhere energy is kept, never invented. What the main path sends
//    back (this, and F at a later entry) joins the entry's reflection weight, its hall and its
//    visitors: between parallel walls it leaves along the entry's mirror direction, and it costs
//    no lookup; a followed branch's leaves through the face it last reflected from;
//  * inside a volume (thickness > 0), Beer-Lambert absorption over each segment's length with
//    sigma = -ln(attenuation_colour) / attenuation_distance; thin-walled materials (thickness 0)
//    pass light straight through, unbent;
//  * the light not transmitted at a later interface ((1 - transmission) of a partly
//    transmissive material) is lit by the IBL's irradiance as a Lambert surface.
// The path that leaves the relic walks the voxel grid and pyramids for the visitors seen through
// it (the foreground walk's ray, per frame) and reads the prefiltered IBL at the transmitted lobe's
// width (every IBL read of transmitted light through the panorama's proxy from where the light
// leaves, the hall's parallax as the static shading has it): each rough refraction widens it by GGX alpha
// |ior - 1| / 2 (in quadrature, times transmitted_roughness_scale), each rough internal reflection by alpha.
// At the depth cap the energy still inside goes to the IBL along the last direction.
//
// Sparse paths (TracerSettings::refraction_stride s > 1): paths are traced only at anchors, the
// pixel centres (x, y) with x and y multiples of s, and every other sample takes the bilinear blend
// of the anchors around it where all of them are on the same smooth piece of the relic as the
// sample (same material, normals within ~25 degrees, the anchor near the sample's tangent plane)
// and agree on what the light does inside (the same events, all exited or all capped, exit
// directions within ~8 degrees); elsewhere (silhouettes, creases, the rim, where the exit
// direction turns fast) the sample traces its own path. What is blended is the path per unit of
// light entering, times the sample's own entry weight (its exact Fresnel and tint), so a blend
// keeps the white furnace; the exit ray's IBL is read along the blended direction. The anchors off
// the coarse lattice (every second anchor each way) blend the coarse anchors likewise (exit
// directions within ~2 degrees) and trace where these disagree. The visitors seen through the
// glass are walked along the traced paths' exit rays; a blended sample or anchor takes the blend
// of its anchors' walks where these see the same, and walks its own exit ray elsewhere.
//
// Supersampling (TracerSettings::refraction_supersample_contrast C > 0): where the transmitted
// light of a four-sample pixel's samples (before the visitors) spans more than C in luminance (a
// sparkle: some of the pixel's rays see a lamp through a crystal's facets, the others do not),
// each of its transmissive samples takes the mean of 16 paths on a 4x4 grid across its quarter of
// the pixel (the rotated grid puts one sample in each quarter). Each is a further primary ray
// (those that miss the relic or meet an opaque material are left out of the mean) traced through
// the relic like the sample's own, and its exit ray is walked for the visitors every frame. The
// entry's own reflection and diffuse stay the sample's. Pixels with one sample (the live loop's
// edge anti-aliasing leaves a facet's inside so) are not measured.
//
// Internal depth: measureInternalDepth traces probe rays from a sphere of directions around the
// relic with a cap of kMaxInternalDepth and keeps the share of the transmitted light still being
// followed after k events; the plan takes the smallest k whose share is below
// TracerSettings::refraction_residual.
//
// Clearcoat: a smooth-to-rough dielectric layer of IOR 1.5: coat = clearcoat x (split-sum
// 0.04 A + B of its roughness), reading the IBL at the clearcoat roughness along the mirror of the
// coat's own normal (its normal map's, else the base's) and the base's walked foreground; the base
// below (reflection, diffuse, transmission) is scaled by 1 - clearcoat x Schlick(0.04, n.v) of the
// coat's normal. Weight, roughness, and the entry's transmission and thickness, are the factors
// times their textures as the hit point sampled them.
#pragma once

#include <cstdint>
#include <vector>

#include <tbb/concurrent_vector.h>

#include "holo/reflect/foreground_pyramid.hpp"
#include "holo/reflect/tracer_settings.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reflect {

class ForegroundWalk;

inline constexpr int kMaxInternalDepth = 32;

// A transmitted path from a hit point through the relic.
struct TransmittedPath {
  vec3 scale{0.0f};        // radiance factor of what the exit ray sees
  vec3 environment{0.0f};  // the prefiltered IBL along the exit ray at the lobe's width
  vec3 resolved{0.0f};     // radiance already read from the IBL on the way (untransmitted light,
                           // the cap's remainder)
  vec3 reflected{0.0f};    // weight of the light sent back towards the viewer's side (reflected
                           // at a later interface, or inside and out again): joins the entry's
                           // reflection (its environment and its visitors)
  vec3 exit_position{0.0f}, exit_direction{0.0f, 0.0f, 1.0f};
  float roughness = 0.0f;  // of the transmitted lobe at the exit (perceptual)
  vec3 entry{0.0f};        // weight of the light entering at the first event: (1 - F)(1 - metallic)
                           // transmission base_colour; scale, resolved and reflected include it
  bool exited = false;     // the path left the relic before the cap (its exit ray can be walked)
  int events = 0;          // interface events followed
  std::uint32_t rays = 0;  // Embree rays cast
};

// Traces the light entering at `position` (shading normal `normal` on the viewer's side) along
// `direction` (into the surface) through the relic, the entry's Fresnel and transmission weight
// included; entry_textured (optional): the entry's base colour, metallic, roughness, transmission and
// thickness as the hit point sampled them from textures (later hits read the factors). `alive` (optional,
// kMaxInternalDepth + 1 entries) gets the luminance of the energy still being followed after each event count
// added.
TransmittedPath traceTransmission(const RenderScene& scene, const PrefilteredIbl& ibl,
                                  const TracerSettings& settings, int depth, const vec3& position,
                                  const vec3& normal, const vec3& direction, const Material& material,
                                  const SurfaceMaterial* entry_textured = nullptr,
                                  std::vector<double>* alive = nullptr);

struct InternalDepth {
  int depth = 1;
  float residual = 0.0f;         // share of the transmitted light still inside at that depth
  std::vector<double> left;      // the share after k = 0..kMaxInternalDepth events
  std::uint32_t probes_hit = 0;  // probe rays that met a transmissive material
};
// The smallest depth whose residual is below `residual_limit` (kMaxInternalDepth when none is),
// from a fixed set of probe rays (deterministic). A relic without transmission: depth 1, 0 left.
InternalDepth measureInternalDepth(const RenderScene& scene, const PrefilteredIbl& ibl,
                                   const TracerSettings& settings, float residual_limit);

// Where a sample's visitors seen through the relic come from: the walk of its own exit ray
// (anchors == 0, shared < 0 and supersampled < 0), of the pixel's sub-sample whose path it shares
// (shared, a sample index), the blend of the walks of the anchors its path blended, with the same
// weights, or the walks of its supersampled paths (supersampled, an index into
// LayerBuffers::supersampled).
struct WalkSource {
  std::uint32_t anchor[4] = {};  // indices into LayerBuffers::anchors
  float weight[4] = {};          // sum to 1
  std::uint8_t anchors = 0;
  std::int32_t shared = -1;
  std::int32_t supersampled = -1;
};

// A sample whose transmitted light is the mean of the paths across its quarter of the pixel:
// those of a grid of primary rays there that meet a transmissive material (its own path alone
// where none does).
struct SupersampledPaths {
  static constexpr int kGrid = 4;  // rays per side of the quarter
  static constexpr int kMaxPaths = kGrid * kGrid;
  int count = 0;  // paths[0, count), entry weights applied
  TransmittedPath paths[kMaxPaths];
};

// Per sample of a view's hit points: the transmitted path and the coat.
struct SampleLayers {
  vec3 transmit_scale{0.0f}, transmit_environment{0.0f};
  vec3 exit_position{0.0f}, exit_direction{0.0f, 0.0f, 1.0f};
  float exit_roughness = 0.0f;
  bool walks = false;  // the exit ray's visitors are read (walked, or blended per `source`)
  WalkSource source;
  vec3 coat_scale{0.0f}, coat_environment{0.0f};
};

// A traced path at an anchor pixel (refraction_stride > 1), per unit of light entering.
struct RefractionAnchor {
  vec3 position{0.0f}, normal{0.0f, 1.0f, 0.0f};
  const Material* material = nullptr;  // null: no anchor there
  TransmittedPath unit;                // scale, resolved and reflected per unit entry weight
  WalkSource source;                   // the coarse anchors it blended (their indices), if it did
};

struct LayerBuffers {
  std::vector<SampleLayers> layers;  // per entry of hits.hits; meaningful where layered[i]
  std::vector<std::uint8_t> layered;
  std::vector<ForegroundSample> transmitted_fg;  // per entry, this frame's visitors along the exit rays
  std::vector<RefractionAnchor> anchors;         // the anchor grid, row-major (kept with the static shading)
  std::vector<ForegroundSample> anchor_fg;       // per anchor, this frame's walk of its exit ray
  tbb::concurrent_vector<SupersampledPaths> supersampled;  // in no fixed order
};

struct LayerCounts {
  std::uint64_t refraction_rays = 0;    // Embree rays of the transmitted paths
  std::uint64_t refracted_samples = 0;  // samples with a transmitted path (traced or blended)
  std::uint64_t capped_paths = 0;       // paths that reached the depth cap
  std::uint64_t coated_samples = 0;
  std::uint64_t supersampled_samples = 0;  // samples whose transmitted light is a mean of paths
};

class MaterialLayers {
 public:
  // Everything must outlive this. refraction / clearcoat: whether the plan runs them.
  MaterialLayers(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                 int internal_depth, bool refraction, bool clearcoat);

  // Every valid sample of a covered pixel with a transmissive or coated material: its shading
  // rescaled (the reflection by the exact Fresnel, the diffuse by 1 - transmission, the base by
  // the coat), its layers written. shading as StaticShading wrote it; `view`: the camera the hit
  // points were traced from (the supersampled paths' primary rays).
  LayerCounts shade(const HitPointBuffer& hits, const CameraModel& view,
                    std::vector<SplitSumShading>& shading, LayerBuffers& buffers) const;
  // This frame's visitors along the exit rays into buffers.transmitted_fg: the anchors' exit rays
  // and those of the samples that traced their own path are walked, a blended sample takes the
  // blend of its anchors' walks where these see the same (the transmitted lobe is blurred like its
  // path) and walks its own elsewhere. Returns the rays walked.
  std::uint64_t walkTransmitted(const HitPointBuffer& hits, const ForegroundWalk& walk,
                                LayerBuffers& buffers) const;

 private:
  // Whether a four-sample pixel's transmitted light spans more than the supersampling contrast.
  bool sparkles(const TransmittedPath (&paths)[4], const bool (&transmits)[4]) const;
  // The paths across a sub-sample's quarter of the pixel (`offset` from the pixel's `centre`),
  // `own` where none meets the glass; returns the Embree rays cast.
  std::uint64_t supersample(const CameraModel& view, const vec2& centre, const vec2& offset,
                            const TransmittedPath& own, SupersampledPaths& more) const;

  const RenderScene& scene_;
  const PrefilteredIbl& ibl_;
  const TracerSettings& settings_;
  int depth_;
  bool refraction_, clearcoat_;
  float dark_ = 0.0f;  // radiance below which the supersampling contrast is not measured
};

}  // namespace holo::reflect
