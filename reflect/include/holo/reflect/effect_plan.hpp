// The frame renderer's effect plan: which passes a frame runs, derived from the scene before any
// work is done, so a disabled or pointless effect costs nothing. The foreground passes (voxel
// grid, pyramids, voxel walk, composition) run only when there is foreground near the relic, a
// camera to read it from, a relic material glossy enough to reflect it (or transmissive, to be
// seen through it), and the effect is on. The material effects run only where a relic material
// calls for them: Refraction (KHR_materials_transmission) with the internal depth measured on the
// relic (refraction_pass.hpp), Clearcoat (KHR_materials_clearcoat); an opaque relic's frame does
// no refraction work at all. SelfOcclusion runs where a relic with a diffuse material shadows
// itself by more than TracerSettings::self_occlusion_min (relic_visibility.hpp, built with the
// renderer; the lobes of metal and glass trace their own interreflection) and, under the light
// shown, changes the displayed relic by at least TracerSettings::effect_min_codes
// (RelicVisibility::largestDisplayedChange, at each panorama's first frame): a convex or
// all-metal relic casts none of its rays, a dim hall at a fixed exposure reads none of them.
// The interreflection (one bounce where a hit point's reflection
// meets the relic itself, static_shading.hpp) runs where the relic can see itself at all: a convex
// relic, every triangle in a supporting plane of the relic (render_scene.hpp), casts none of its
// rays, and on any other relic a ray is cast only where its triangle's plane does not prove a miss.
// AxisAlignedFilter runs where the interreflection runs and some relic material samples its rough
// lobe for it (the one Monte Carlo term of the static shading, interleaved over pixels); a smooth
// or convex relic's frame does no filtering.
// ProgressiveRefinement runs where the interreflection runs and an opaque relic's material traces
// its rough lobe for it (progressive_accumulation.hpp in reflect/src): a still view adds a sample
// set a frame, its cost at most the static pass's on the rough samples, nothing once converged or
// while the foreground keeps changing.
// The sun light (a part of StaticReflections, like the interreflection) runs where the panorama
// has a sun (panorama_sun.hpp: a small region holding much of its light) and some relic material
// is lit diffusely: the sun taken out of the 9-coefficient diffuse light and applied as a
// directional light with a shadow ray against the relic; a panorama without a sun, or a relic with
// nothing diffuse (glass, metal), casts none of its rays.
// VisitorLight (visitor_light.hpp) runs where a foreground point comes within
// TracerSettings::visitor_light_distance of a relic whose diffuse or widest lobes the walk does
// not light, and the visitors' voxels can change a displayed pixel by at least effect_min_codes
// (VisitorLight::largestRadianceChange, every frame, before any splat): the visitors' shadow and
// light on them, with the voxel grid it reads; with no visitor that near the frame does none of
// its work, with visitors that dim (or that far) only the binning that measured them.
// AxisAlignedFilter and ProgressiveRefinement change only how the rough lobe's strata are
// sampled: they run where the lobe's Monte Carlo spread (lobe_spread.hpp in reflect/src, at the
// frame's exposure) reaches effect_min_codes.
// Plinth runs where a plinth is configured; Caustics only where it is and the relic is
// transmissive (a plinth always lies below the relic): an opaque relic or no plinth traces no
// photon.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "holo/core/math.hpp"

namespace holo::reflect {

enum class Pass {
  VoxelGrid,              // bin the foreground cloud
  Pyramids,               // Kawase colour and mask pyramids per camera
  RoughForegroundMap,     // the visitors prefiltered around the relic, for its roughest materials
  HitPoints,              // primary rays against the relic (psi_r, coverage)
  SelfOcclusion,          // the static shading's light occluded by the relic itself (relic_visibility.hpp)
  StaticReflections,      // prefiltered IBL (psi_s) and diffuse
  AxisAlignedFilter,      // the rough lobe's sampled interreflection filtered (axis_aligned_filter.hpp)
  Refraction,             // transmitted paths through the relic to the IBL (static, like the hit points)
  Clearcoat,              // the coat's specular lobe over the base (static shading and composition)
  ProgressiveRefinement,  // a still view's rough interreflection: one more sample set accumulated
  ForegroundWalk,         // voxel walk + pyramid reads (psi_d, w)
  RefractedForeground,    // the visitors seen through the relic: a walk per transmitted exit ray
  Composition,            // psi_d * w + psi_s * (1 - w)
  VisitorLight,  // the visitors' shadow and light on the diffuse and widest lobes (visitor_light.hpp)
  Caustics,      // the transmissive relic's caustic on the plinth (caustic_tracer.hpp), when relit
  Plinth,        // the virtual plinth: its top's light when relit, and its pixels in each view
  ToneMap,       // exposure, tone mapping, sRGB (the last: pipeline's kPassCount counts on it)
};

const char* passName(Pass pass);

// A relic material this rough or rougher (and not metallic-textured) is treated as not glossy:
// its reflection lobe is wider than ~80 degrees and the foreground reads the top pyramid level.
inline constexpr float kGlossyRoughnessLimit = 0.9f;

struct EffectInputs {
  bool foreground_enabled = true;  // the user's switch
  bool relic_empty = false;
  bool relic_glossy = true;  // some relic material below kGlossyRoughnessLimit
  bool relic_rough = false;  // some relic material takes its foreground from the rough map
  std::size_t foreground_points = 0;
  std::size_t cameras = 0;
  Bounds3 relic_bounds;
  Bounds3 foreground_bounds;             // empty when there is no foreground
  float max_reflection_distance = 3.0f;  // metres: the voxel walk's reach
  bool relic_transmissive = false;       // some relic material has transmission > 0
  bool relic_clearcoat = false;          // some relic material has clearcoat > 0
  bool refracted_foreground = true;      // the user's switch for the visitors seen through glass
  // Interface events a transmitted path follows (measured on the relic or set, >= 1) and the share
  // of the transmitted light still inside the relic at that depth (goes to the IBL).
  int internal_depth = 0;
  float internal_residual = 0.0f;
  std::string internal_depth_source;  // "measured" or "set"
  // The relic's visibility was built and occludes enough to show; why or why not, for the plan's
  // reason ("self-occlusion (6305 vertex sides, up to 52% occluded)", "convex relic: no
  // self-occlusion", ...).
  bool self_occlusion = false;
  std::string self_occlusion_reason;
  // A relic material traces its rough lobe's strata, the relic is opaque and refinement is on;
  // why or why not, for the plan's reason ("rough lobes refined up to 64 sets", ...).
  bool progressive_refinement = false;
  std::string progressive_refinement_reason;
  // The visitors' light: the user's switch, whether some relic surface takes the hall's light by
  // a diffuse or a lobe the walk leaves (rough >= kGlossyRoughnessLimit), and whether some
  // foreground point lies within TracerSettings::visitor_light_distance of the relic's box (the
  // renderer looks, stopping at the first; the box of visitors all round holds the relic).
  bool visitor_light_enabled = true;
  bool relic_lit_diffusely = false;
  bool visitor_within_light_distance = false;
  // The most the visitors can change a displayed relic pixel this frame, sRGB codes
  // (VisitorLight::largestRadianceChange at the frame's exposure); infinite: not measured (no
  // exposure chosen yet), the distance alone decides. VisitorLight runs only from
  // effect_min_codes (TracerSettings') up.
  float visitor_light_codes = std::numeric_limits<float>::infinity();
  float effect_min_codes = 1.0f;
  // Some relic material samples its rough lobe for the interreflection (interleaved), and the
  // filter is on; why or why not, for the plan's reason.
  bool lobe_filter = false;
  std::string lobe_filter_reason;
  bool interreflection = true;  // the user's switch (TracerSettings::relic_interreflection)
  // Every relic triangle lies in a supporting plane of the relic (RenderScene::relicIsConvex):
  // a ray leaving its surface outwards cannot meet it again.
  bool relic_convex = false;
  // A plinth is configured (TracerSettings::plinth) and the caustic on it is on
  // (TracerEvaluationKnobs::plinth_caustic). The caustic needs a transmissive relic (with
  // refraction on) above it: relic_transmissive.
  bool plinth = false;
  bool plinth_caustic = true;
  // The user's switch for the sun light (TracerEvaluationKnobs::sun_light), whether the panorama
  // has a sun and what was found (PanoramaSun::describe).
  bool sun_light_enabled = true;
  bool panorama_sun = false;
  std::string panorama_sun_description;
};

struct EffectPlan {
  std::vector<Pass> passes;
  std::string foreground_reason;     // why the foreground passes run or not, for the statistics
  std::string material_reason;       // why the material passes run or not
  int internal_depth = 0;            // interface events per transmitted path; 0 without Refraction
  std::string visitor_light_reason;  // why VisitorLight runs or not
  // The static shading casts the interreflection's rays (static_shading.hpp); false for a convex
  // relic or with the effect off. A part of the StaticReflections pass, timed with it.
  bool interreflection = false;
  std::string plinth_reason;  // why Plinth and Caustics run or not
  // The static shading lights the relic's diffuse surfaces with the panorama's sun as a
  // directional light with a shadow ray (static_shading.hpp); a part of StaticReflections.
  bool sun_light = false;
  bool has(Pass pass) const;
  // "HitPoints,StaticReflections,ToneMap (no foreground points; opaque relic, no clearcoat,
  // convex relic: no interreflection; no visitor near enough to light the relic)"
  std::string describe() const;
};

EffectPlan planEffects(const EffectInputs& inputs);

}  // namespace holo::reflect
