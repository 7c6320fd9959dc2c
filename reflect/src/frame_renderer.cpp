#include "holo/reflect/frame_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>

#include <tbb/parallel_for.h>

#include "axis_aligned_filter.hpp"
#include "compose_pass.hpp"
#include "composed_images.hpp"
#include "foreground_walk.hpp"
#include "holo/reflect/tone_map.hpp"
#include "internal_depth.hpp"
#include "lobe_effect_gate.hpp"
#include "lobe_spread.hpp"
#include "pass_timer.hpp"
#include "plinth_light.hpp"
#include "progressive_accumulation.hpp"
#include "refraction_pass.hpp"
#include "static_pass_schedule.hpp"
#include "static_shading.hpp"
#include "wide_lobe_cache.hpp"

namespace holo::reflect {

namespace {

bool reusable(const CameraModel& cached, const CameraModel& wanted, float distance) {
  if (cached.width() != wanted.width() || cached.height() != wanted.height()) return false;
  if (distance <= 0.0f)
    return cached.T_world_camera() == wanted.T_world_camera() &&
           cached.intrinsics().fx == wanted.intrinsics().fx &&
           cached.intrinsics().fy == wanted.intrinsics().fy &&
           cached.intrinsics().cx == wanted.intrinsics().cx &&
           cached.intrinsics().cy == wanted.intrinsics().cy &&
           cached.intrinsics().distortion == wanted.intrinsics().distortion;
  // A moved eye: the position within `distance`, the optical axis turned by less than a point
  // half a metre ahead moves, the focal length within 1%.
  const vec3 axis_a = glm::normalize(vec3(cached.T_world_camera()[2]));
  const vec3 axis_b = glm::normalize(vec3(wanted.T_world_camera()[2]));
  return glm::distance(cached.position(), wanted.position()) <= distance &&
         glm::length(axis_a - axis_b) <= distance / 0.5f &&
         std::abs(cached.intrinsics().fx - wanted.intrinsics().fx) <= 0.01f * wanted.intrinsics().fx &&
         std::abs(cached.intrinsics().fy - wanted.intrinsics().fy) <= 0.01f * wanted.intrinsics().fy;
}

// Bins per side of the wide lobes' eye-direction grid (wide_lobe_cache.hpp): 6 x 6 over the
// hemisphere, about 25 degrees apart, where a lobe at least kGlossyRoughnessLimit rough is over 90
// degrees wide.
constexpr int kWideLobeBins = 6;

std::uint64_t hashCombine(std::uint64_t seed, std::uint64_t value) {
  return seed ^ (value + 0x9e3779b97f4a7c15ull + (seed << 6) + (seed >> 2));
}

// Some relic surface reflects diffusely (a base colour not all metal nor glass, or textured so).
bool relicHasDiffuse(const RenderScene& scene) {
  const auto diffuse = [](float metallic, float transmission) {
    return (1.0f - metallic) * (1.0f - transmission) > 0.0f;
  };
  if (const auto& m = scene.relicMaterialOverride()) return diffuse(m->metallic, m->transmission);
  if (scene.relic().materials.empty()) return diffuse(Material{}.metallic, Material{}.transmission);
  for (const Material& m : scene.relic().materials)
    if (m.metallic_roughness_texture.used() || m.transmission_texture.used() ||
        diffuse(m.metallic, m.transmission))
      return true;
  return false;
}

}  // namespace

FrameRenderer::FrameRenderer(const RenderScene& scene, const PrefilteredIbl& ibl, TracerSettings settings)
    : scene_(scene), ibl_(ibl), settings_((settings.validate(), settings)), grid_(settings_.grid) {
  for (const Material& m : scene_.relic().materials)
    if (m.roughness < kGlossyRoughnessLimit || m.metallic_roughness_texture.used()) relic_glossy_ = true;
  if (scene_.relic().materials.empty()) relic_glossy_ = true;  // default material: be safe
  relic_lit_diffusely_ = relicHasDiffuse(scene_) || !relic_glossy_;
  for (const Material& m : scene_.relic().materials)
    relic_wide_lobes_ = relic_wide_lobes_ || m.roughness >= kGlossyRoughnessLimit;
  if (scene_.relic().materials.empty()) relic_wide_lobes_ = Material{}.roughness >= kGlossyRoughnessLimit;
  if (const auto& m = scene_.relicMaterialOverride())
    relic_wide_lobes_ = relic_wide_lobes_ || m->roughness >= kGlossyRoughnessLimit;
  relic_lit_diffusely_ = relic_lit_diffusely_ || relic_wide_lobes_;
  relic_bounds_ = scene_.relicBounds();
  for (const Material& m : scene_.relic().materials) {
    relic_transmissive_ =
        relic_transmissive_ || (settings_.evaluation.refraction_enabled && m.transmission > 0.0f);
    relic_clearcoat_ = relic_clearcoat_ || m.clearcoat > 0.0f;
  }
  if (relic_transmissive_) {
    if (settings_.refraction_depth > 0) {
      internal_depth_ = settings_.refraction_depth;
    } else {
      const InternalDepth measured =
          measureInternalDepth(scene_, ibl_, settings_, settings_.refraction_residual);
      internal_depth_ = measured.depth;
      internal_residual_ = measured.residual;
    }
  }
  if (!settings_.evaluation.self_occlusion) {
    self_occlusion_reason_ = "self-occlusion off";
  } else if (scene_.relic().triangleCount() == 0 || scene_.relicIsConvex()) {
    self_occlusion_reason_ = "convex relic: no self-occlusion";
  } else if (!relicHasDiffuse(scene_)) {
    // All its light is reflected by lobes the interreflection traces.
    self_occlusion_reason_ = "no diffuse relic material: no self-occlusion";
  } else {
    auto visibility = std::make_unique<RelicVisibility>(
        scene_, RelicVisibilitySettings{settings_.self_occlusion_rays, settings_.self_occlusion_bounces,
                                        settings_.ray_offset});
    char figures[96];
    std::snprintf(figures, sizeof figures, "%zu vertex sides, up to %.0f%% occluded",
                  visibility->vertexSides(), double(visibility->maxOcclusion()) * 100.0);
    if (visibility->maxOcclusion() >= settings_.self_occlusion_min) {
      visibility_ = std::move(visibility);
      self_occlusion_figures_ = figures;
      self_occlusion_reason_ = std::string("self-occlusion (") + figures + ")";
    } else {
      self_occlusion_reason_ = std::string("no self-occlusion to show (") + figures + ")";
    }
  }
  std::vector<float> rough;
  for (const Material& m : scene_.relic().materials)
    if (!m.metallic_roughness_texture.used() && m.roughness >= settings_.foreground_map_roughness &&
        m.roughness < kGlossyRoughnessLimit &&
        std::find(rough.begin(), rough.end(), m.roughness) == rough.end())
      rough.push_back(m.roughness);
  if (!rough.empty()) {
    std::sort(rough.begin(), rough.end());
    if (rough.size() > 8) rough.resize(8);  // the map's limit; rougher ones read the nearest
    rough_map_ = std::make_unique<RoughForegroundMap>(settings_.foreground_map_width, rough);
  }
  if (settings_.evaluation.wide_lobe_cache && settings_.relic_interreflection &&
      settings_.rough_interreflection_grid > 1) {
    wide_lobes_ = std::make_unique<WideLobeCache>(scene_, kWideLobeBins);
    if (!wide_lobes_->active()) wide_lobes_.reset();
  }
  // The rough lobe's strata are the static shading's one Monte Carlo term: the refinement and the
  // filter work on them only where some material samples them, interleaved over pixels (the
  // wide lobes' cache holds no noise).
  const bool samples_lobe =
      settings_.relic_interreflection && settings_.evaluation.rough_interreflection_interleaved &&
      StaticShading(scene_, ibl_, settings_, rough_map_.get(), nullptr, nullptr, wide_lobes_.get())
          .tracesLobes();
  const bool layered = relic_transmissive_ || relic_clearcoat_;
  refines_ = settings_.refinement_sets > 1 && samples_lobe && !layered;
  refinement_reason_ =
      settings_.refinement_sets <= 1 ? "progressive refinement off"
      : !samples_lobe                ? "no rough lobe sampled: no progressive refinement"
      : layered                      ? "layered relic: no progressive refinement"
                : "rough lobes refined up to " + std::to_string(settings_.refinement_sets) + " sets";
  lobe_filter_ = samples_lobe && settings_.evaluation.axis_aligned_filter;
  lobe_filter_reason_ = !samples_lobe  ? "no sampled rough lobe: no filter"
                        : lobe_filter_ ? "axis-aligned filter of the rough lobe"
                                       : "axis-aligned filter off";
  if (settings_.plinth && scene_.relic().triangleCount() > 0)
    plinth_light_ =
        std::make_unique<PlinthLight>(placePlinth(*settings_.plinth, relic_bounds_),
                                      settings_.plinth_map_resolution, settings_.plinth_shadow_rays);
}

const CausticImage* FrameRenderer::plinthCaustic() const {
  return plinth_light_ && !plinth_light_->caustic().irradiance.empty() ? &plinth_light_->caustic() : nullptr;
}

bool FrameRenderer::visitorWithinReach(const depthfilter::ForegroundCloud& cloud) const {
  if (!settings_.evaluation.visitor_light || !relic_lit_diffusely_) return false;
  const float reach2 = settings_.visitor_light_distance * settings_.visitor_light_distance;
  for (const depthfilter::ForegroundPoint& p : cloud.points) {
    const vec3 gap =
        glm::max(glm::max(relic_bounds_.lo - p.position, p.position - relic_bounds_.hi), vec3(0.0f));
    if (glm::dot(gap, gap) <= reach2) return true;
  }
  return false;
}

float FrameRenderer::gateExposure() const {
  return settings_.exposure > 0.0f ? settings_.exposure : last_exposure_;
}

EffectPlan FrameRenderer::plan(const depthfilter::ForegroundCloud& cloud,
                               const std::vector<ForegroundCameraImage>& cameras) const {
  return planFrame(cloud, cameras, visitorWithinReach(cloud), std::numeric_limits<float>::infinity(),
                   std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity());
}

std::uint64_t FrameRenderer::lightKey() const {
  float turn = ibl_.relicTurn();
  std::uint32_t turn_bits = 0;
  std::memcpy(&turn_bits, &turn, sizeof turn_bits);
  return hashCombine(ibl_.sourceHash(), turn_bits);
}

EffectPlan FrameRenderer::planFrame(const depthfilter::ForegroundCloud& cloud,
                                    const std::vector<ForegroundCameraImage>& cameras, bool visitor_near,
                                    float visitor_codes, float filter_codes, float refinement_codes) const {
  EffectInputs in;
  in.foreground_enabled = settings_.foreground_enabled;
  in.relic_empty = scene_.relic().triangleCount() == 0;
  in.relic_glossy = relic_glossy_;
  in.relic_rough = rough_map_ != nullptr;
  in.foreground_points = cloud.points.size();
  in.cameras = cameras.size();
  in.relic_bounds = scene_.relicBounds();
  if (!cloud.empty()) in.foreground_bounds = cloud.bounds();
  in.max_reflection_distance = settings_.max_reflection_distance;
  in.relic_transmissive = relic_transmissive_;
  in.relic_clearcoat = relic_clearcoat_;
  in.refracted_foreground = settings_.evaluation.refracted_foreground;
  in.internal_depth = internal_depth_;
  in.internal_residual = internal_residual_;
  in.internal_depth_source = settings_.refraction_depth > 0 ? "set" : "measured";
  in.sun_light_enabled = settings_.evaluation.sun_light;
  in.panorama_sun = ibl_.sun().found;
  in.panorama_sun_description = ibl_.sun().describe();
  in.self_occlusion = visibility_ != nullptr;
  in.self_occlusion_reason = self_occlusion_reason_;
  if (visibility_ && lit_) {  // the displayed change under this light decides
    char codes[64];
    std::snprintf(codes, sizeof codes, "%.2g sRGB codes", double(self_occlusion_codes_));
    in.self_occlusion = self_occlusion_codes_ >= settings_.effect_min_codes;
    in.self_occlusion_reason =
        std::string(in.self_occlusion ? "self-occlusion (" : "self-occlusion not shown (") +
        self_occlusion_figures_ + ", at most " + codes + " under this light)";
  }
  // The filter and the refinement change only how the lobe is sampled: they run where its Monte
  // Carlo spread can show.
  const float exposure = gateExposure();
  const float lobe_codes =
      (refines_ || lobe_filter_) && exposure > 0.0f
          ? largestCodeChange(lobeSpread(scene_, ibl_, settings_.rough_interreflection_grid), exposure)
          : std::numeric_limits<float>::infinity();
  const bool lobe_shows = lobe_codes >= settings_.effect_min_codes;
  char lobe[64] = "";
  if (std::isfinite(lobe_codes))
    std::snprintf(lobe, sizeof lobe, "at most %.2g sRGB codes", double(lobe_codes));
  // Where their spread can show, the refinement's own change where it last ran decides.
  const bool refinement_shows = refinement_codes >= settings_.effect_min_codes;
  char refined[64] = "";
  if (std::isfinite(refinement_codes))
    std::snprintf(refined, sizeof refined, "%.2g sRGB codes where it last ran", double(refinement_codes));
  in.progressive_refinement = refines_ && lobe_shows && refinement_shows;
  in.progressive_refinement_reason =
      !refines_ || !std::isfinite(lobe_codes) ? refinement_reason_
      : !lobe_shows ? std::string("progressive refinement: the rough lobes' spread not shown (") + lobe + ")"
      : !refinement_shows               ? std::string("progressive refinement not shown (") + refined + ")"
      : std::isfinite(refinement_codes) ? refinement_reason_ + " (their spread " + lobe + ", " + refined + ")"
                                        : refinement_reason_ + " (their spread " + lobe + ")";
  in.visitor_light_enabled = settings_.evaluation.visitor_light;
  in.relic_lit_diffusely = relic_lit_diffusely_;
  in.visitor_within_light_distance = visitor_near;
  in.visitor_light_codes = visitor_codes;
  in.effect_min_codes = settings_.effect_min_codes;
  // Where its noise can show, the filter's own change where it last ran decides.
  const bool filter_shows = filter_codes >= settings_.effect_min_codes;
  char last[64] = "";
  if (std::isfinite(filter_codes))
    std::snprintf(last, sizeof last, "%.2g sRGB codes where it last ran", double(filter_codes));
  in.lobe_filter = lobe_filter_ && lobe_shows && filter_shows;
  in.lobe_filter_reason =
      !lobe_filter_ || !std::isfinite(lobe_codes) ? lobe_filter_reason_
      : !lobe_shows   ? std::string("axis-aligned filter: the rough lobe's noise not shown (") + lobe + ")"
      : !filter_shows ? std::string("axis-aligned filter not shown (") + last + ")"
      : std::isfinite(filter_codes) ? lobe_filter_reason_ + " (its noise " + lobe + ", " + last + ")"
                                    : lobe_filter_reason_ + " (its noise " + lobe + ")";
  in.interreflection = settings_.relic_interreflection;
  in.relic_convex = scene_.relicIsConvex();
  in.plinth = plinth_light_ != nullptr;
  in.plinth_caustic = settings_.evaluation.plinth_caustic;
  return planEffects(in);
}

struct FrameRenderer::ViewCache {
  CameraModel camera;
  bool ready = false;
  HitPointBuffer hits;
  std::vector<SplitSumShading> shading;  // per entry of hits.hits
  std::vector<WalkRay> walk_rays;        // per entry of hits.hits
  ViewBounces bounces;                   // the static shading's rough lobes
  std::vector<ForegroundSample> fg;      // per entry of hits.hits, this frame's walk (scratch)
  WalkScratch walk;
  LayerBuffers layers;  // per entry of hits.hits, with Refraction or Clearcoat
  // With Plinth: the pixels it was drawn in, and those with the relic's covered ones (ascending):
  // what a fixed exposure tone-maps.
  std::vector<std::uint32_t> plinth_pixels, shown;
  // The static result. Never written once handed out: a rebuild allocates new images, so a
  // caller's FrameResult keeps the pixels it was given.
  cv::Mat hdr, coverage, display, zero_weight;
  float display_exposure = 0.0f;  // the exposure `display` was tone-mapped at; 0: none
  // Changes whenever hdr, display or hits.covered do: what `composed` restores its images from.
  std::uint64_t static_version = 0;
  ComposedImages composed;           // with ForegroundWalk: the images handed out, over the static ones
  ProgressiveAccumulation progress;  // with ProgressiveRefinement
  // With VisitorLight: what the static shading fixes of each sample's response to the visitors'
  // light; stale once the shading changes (a new static pass or a refinement step).
  VisitorLight::Receivers visitor_receivers;
  bool receivers_ready = false;
  // Whether the axis-aligned filter shows in this view, and its last static pass's pixels without
  // and with it (scratch; written where the filter ran); whether its refinement shows.
  LobeEffectGate filter_gate;
  LobeEffectGate refinement_gate;
  std::vector<FilterChange> filter_changes;
  float shown_exposure = 0.0f;  // the exposure the view was last shown at
  int deferred_frames = 0;      // frames in a row its due static passes were left to a later one
};

FrameRenderer::~FrameRenderer() = default;

void FrameRenderer::setExposure(float exposure) {
  settings_.exposure = exposure;
  for (auto& cache : caches_) cache->display_exposure = 0.0f;
}

FrameResult FrameRenderer::render(const depthfilter::ForegroundCloud& cloud,
                                  const std::vector<ForegroundCameraImage>& cameras,
                                  const std::vector<CameraModel>& views) {
  FrameResult result;
  // The visibility lit before the plan: whether it shows (effect_min_codes) depends on the light.
  // Without the sun where the plan will light the relic with it (EffectPlan::sun_light: the
  // visibility is only built for a relic lit diffusely).
  const bool sun_as_light = settings_.evaluation.sun_light && ibl_.sun().found && relic_lit_diffusely_;
  if (visibility_ && (!lit_ || lit_source_ != ibl_.sourceHash() || lit_turn_ != ibl_.relicTurn() ||
                      lighting_.without_sun != sun_as_light)) {
    PassTimer t(result.frame_timings, Pass::SelfOcclusion);
    // A turning relic is lit from the transfer alone: filtering every stratum again at every
    // turn step would cost a still relic's first frame every frame.
    lighting_ = visibility_->lit(ibl_, ibl_.relicTurn() == 0.0f, sun_as_light);
    self_occlusion_codes_ = visibility_->largestDisplayedChange(lighting_, ibl_, settings_.exposure);
    lit_source_ = ibl_.sourceHash();
    lit_turn_ = ibl_.relicTurn();
    lit_ = true;
    for (auto& cache : caches_) cache->ready = false;  // shaded with the old lighting
  }
  // Which views trace their static passes this frame: before the plan, whose gates keep a view's
  // last check where it shows its cache, and again before the views (a new light clears the caches).
  const auto schedule = [&] {
    std::vector<ViewReuseState> states(views.size());
    for (std::size_t v = 0; v < views.size() && v < caches_.size(); ++v) {
      const ViewCache& cache = *caches_[v];
      ViewReuseState& state = states[v];
      state.cache_shown = cache.ready && cache.camera.width() == views[v].width() &&
                          cache.camera.height() == views[v].height();
      state.within_reuse =
          state.cache_shown && reusable(cache.camera, views[v], settings_.static_reuse_distance);
      state.within_defer =
          state.cache_shown && reusable(cache.camera, views[v], settings_.static_defer_distance);
      state.moved = glm::distance(cache.camera.position(), views[v].position());
      state.waited = cache.deferred_frames;
    }
    return scheduleStaticPasses(states, settings_.static_retraces_per_frame);
  };
  std::vector<StaticPass> passes = schedule();
  std::vector<bool> shows_cache(views.size());
  for (std::size_t v = 0; v < views.size(); ++v) shows_cache[v] = passes[v] != StaticPass::Trace;
  // The visitors near enough are binned before the plan, which weighs what their voxels can show.
  const bool visitor_near = visitorWithinReach(cloud);
  float visitor_codes = std::numeric_limits<float>::infinity();
  bool binned = false;
  if (visitor_near) {
    PassTimer t(result.frame_timings, Pass::VoxelGrid);
    grid_.build(cloud);
    binned = true;
    if (const float exposure = gateExposure(); exposure > 0.0f)
      visitor_codes = largestCodeChange(
          VisitorLight::largestRadianceChange(grid_, relic_bounds_, ibl_.brightest(), relic_wide_lobes_),
          exposure);
  }
  const std::vector<float> refinement_codes = refinementCodes(views);
  const float any_refinement_codes =
      refinement_codes.empty() ? std::numeric_limits<float>::infinity()
                               : *std::max_element(refinement_codes.begin(), refinement_codes.end());
  result.plan = planFrame(cloud, cameras, visitor_near, visitor_codes, lobeFilterCodes(views, shows_cache),
                          any_refinement_codes);
  if (result.plan.has(Pass::VoxelGrid)) {
    if (!binned) {
      PassTimer t(result.frame_timings, Pass::VoxelGrid);
      grid_.build(cloud);
    }
  } else {
    grid_.clear();
  }
  if (result.plan.has(Pass::VisitorLight)) {
    PassTimer t(result.frame_timings, Pass::VisitorLight);
    if (!visitor_light_) visitor_light_ = std::make_unique<VisitorLight>(settings_.visitor_light_map_width);
    visitor_light_->build(grid_, ibl_, relic_bounds_);
    result.visitor_light_splats = visitor_light_->splats();
    result.visitor_light_texels = visitor_light_->coveredTexels();
  }
  if (result.plan.has(Pass::RoughForegroundMap)) {
    PassTimer t(result.frame_timings, Pass::RoughForegroundMap);
    rough_map_->build(grid_, 0.5f * (relic_bounds_.lo + relic_bounds_.hi));
  }
  // The pyramids are rebuilt in place, keeping their level images from frame to frame.
  for (ForegroundPyramid& pyramid : pyramids_) pyramid.clear();
  if (result.plan.has(Pass::Pyramids)) {
    PassTimer t(result.frame_timings, Pass::Pyramids);
    if (pyramids_.size() < cameras.size()) pyramids_.resize(cameras.size());
    // A camera without an image this frame (live: it dropped out) keeps an empty pyramid; the
    // walk ignores the voxels it saw.
    // One camera per task: a pyramid's levels are sequential, the cameras independent.
    tbb::parallel_for(std::size_t(0), cameras.size(), [&](std::size_t c) {
      if (!cameras[c].colour_bgr.empty())
        pyramids_[c].build(cameras[c].colour_bgr, cameras[c].mask, settings_.pyramid_levels);
    });
  }
  if (result.plan.has(Pass::Plinth) &&
      (!plinth_lit_ || plinth_source_ != ibl_.sourceHash() || plinth_turn_ != ibl_.relicTurn())) {
    CausticImage caustic;
    if (result.plan.has(Pass::Caustics)) {
      PassTimer t(result.frame_timings, Pass::Caustics);
      const PlinthBox& box = plinth_light_->box();
      CausticReceiverGrid grid;
      grid.centre = box.centre;
      grid.half_size = box.half_width;
      grid.height = box.top;
      grid.resolution = settings_.caustic_resolution;
      CausticTracerSettings trace;
      trace.photons = settings_.caustic_photons;
      caustic = traceEnvironmentCaustics(scene_, ibl_, grid, trace);
      result.caustic_photons_traced = caustic.traced;
      result.caustic_photons_stored = caustic.stored;
    }
    PassTimer t(result.frame_timings, Pass::Plinth);
    result.plinth_shadow_rays =
        plinth_light_->light(scene_, ibl_, result.plan.has(Pass::Caustics) ? &caustic : nullptr,
                             settings_.evaluation.plinth_shadow);
    plinth_source_ = ibl_.sourceHash();
    plinth_turn_ = ibl_.relicTurn();
    plinth_lit_ = true;
    for (auto& cache : caches_) cache->ready = false;  // drawn with the old light
  }
  if (wide_lobes_) {
    // The entries hold the static shading of the second points: the light, the relic's turn and
    // what of it the plan runs.
    std::uint64_t key = hashCombine(lightKey(), (result.plan.has(Pass::SelfOcclusion) ? 1u : 0u) |
                                                    (result.plan.sun_light ? 2u : 0u) |
                                                    (result.plan.interreflection ? 4u : 0u));
    if (key != wide_lobes_key_) {
      wide_lobes_->clear();
      wide_lobes_key_ = key;
    }
  }
  while (caches_.size() < views.size()) caches_.push_back(std::make_unique<ViewCache>());
  // Still, for ProgressiveRefinement: what the grid holds is what it held last frame.
  const std::uint64_t foreground =
      result.plan.has(Pass::ProgressiveRefinement) ? foregroundSignature(grid_) : 0;
  passes = schedule();
  for (std::size_t v = 0; v < views.size(); ++v)
    caches_[v]->deferred_frames = passes[v] == StaticPass::Defer ? caches_[v]->deferred_frames + 1 : 0;
  // The views in parallel, each into its own cache and image: a view's passes that run on one
  // thread (hit point spans, copies, tone mapping) overlap with the other views' work. A view reads
  // only what this frame built above (the wide lobes' cache is filled lock-free with values that do
  // not depend on who computes them), so every image is the one a loop over the views gives.
  result.views.resize(views.size());
  tbb::parallel_for(std::size_t(0), views.size(), [&](std::size_t v) {
    const bool refine =
        result.plan.has(Pass::ProgressiveRefinement) && refinement_codes[v] >= settings_.effect_min_codes;
    result.views[v] = renderView(result.plan, cameras, views[v], foreground, refine,
                                 passes[v] == StaticPass::Defer, *caches_[v]);
  });
  if (settings_.exposure <= 0.0f) {
    last_exposure_ = 0.0f;
    for (const ViewImages& view : result.views) last_exposure_ = std::max(last_exposure_, view.exposure);
  }
  return result;
}

std::vector<float> FrameRenderer::gateCodes(const std::vector<CameraModel>& views,
                                            LobeEffectGate ViewCache::*gate,
                                            const std::vector<bool>* shows_cache) const {
  std::vector<float> codes(views.size(), std::numeric_limits<float>::infinity());
  if (caches_.size() < views.size()) return codes;
  const std::uint64_t light = lightKey();
  for (std::size_t v = 0; v < views.size(); ++v) {
    const ViewCache& cache = *caches_[v];
    const float exposure = settings_.exposure > 0.0f ? settings_.exposure : cache.shown_exposure;
    // The filter runs only in a static pass: a view whose static shading is reused keeps its last
    // check. The refinement runs in the reused (still) frames, so its triggers apply there too.
    const bool reused = shows_cache && (*shows_cache)[v];
    codes[v] = (cache.*gate).codes(views[v].position(), exposure, light, reused);
  }
  return codes;
}

float FrameRenderer::lobeFilterCodes(const std::vector<CameraModel>& views,
                                     const std::vector<bool>& shows_cache) const {
  if (!lobe_filter_) return std::numeric_limits<float>::infinity();
  float largest = 0.0f;
  for (const float codes : gateCodes(views, &ViewCache::filter_gate, &shows_cache))
    largest = std::max(largest, codes);
  return largest;
}

std::vector<float> FrameRenderer::refinementCodes(const std::vector<CameraModel>& views) const {
  if (!refines_) return std::vector<float>(views.size(), std::numeric_limits<float>::infinity());
  return gateCodes(views, &ViewCache::refinement_gate, nullptr);
}

ViewImages FrameRenderer::renderView(const EffectPlan& plan,
                                     const std::vector<ForegroundCameraImage>& cameras,
                                     const CameraModel& view, std::uint64_t foreground, bool refine,
                                     bool deferred, ViewCache& cache) const {
  ViewImages out;
  const int w = view.width(), h = view.height();
  const bool fixed_exposure = settings_.exposure > 0.0f;
  if (!plan.has(Pass::HitPoints)) {
    cache.ready = false;
    out.camera = view;
    out.hdr = cv::Mat(h, w, CV_32FC3, cv::Scalar::all(0));
    out.weight = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
    out.coverage = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
    PassTimer t(out.timings, Pass::ToneMap);
    out.exposure = fixed_exposure ? settings_.exposure : 1.0f;
    out.display = cv::Mat(h, w, CV_8UC3, cv::Scalar::all(0));
    return out;
  }

  out.static_reused =
      cache.ready && (deferred || reusable(cache.camera, view, settings_.static_reuse_distance));
  out.static_deferred = deferred && out.static_reused;
  const bool layered = plan.has(Pass::Refraction) || plan.has(Pass::Clearcoat);
  if (!out.static_reused) {
    {
      PassTimer t(out.timings, Pass::HitPoints);
      const AntiAliasing aa = settings_.aa_samples == 4 ? AntiAliasing::Full
                              : settings_.edge_aa       ? AntiAliasing::Edges
                                                        : AntiAliasing::None;
      traceHitPoints(scene_, view, aa, cache.hits, relic_bounds_);
    }
    {
      PassTimer t(out.timings, Pass::StaticReflections);
      // New images (see ViewCache): the previous ones may still be held by a caller. Only the
      // covered pixels have anything to shade; the rest stay black.
      cache.hdr = cv::Mat(h, w, CV_32FC3, cv::Scalar::all(0));
      cache.coverage = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
      cache.zero_weight = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
      TracerSettings planned = settings_;
      planned.relic_interreflection = plan.interreflection;
      planned.evaluation.sun_light = plan.sun_light;
      const AxisAlignedFilter filter;
      FilterCounts filtered;
      const StaticCounts counts =
          StaticShading(scene_, ibl_, planned, rough_map_.get(),
                        plan.has(Pass::SelfOcclusion) ? visibility_.get() : nullptr, &lighting_,
                        wide_lobes_.get())
              .shade(cache.hits, view, cache.shading, cache.walk_rays, cache.bounces, cache.hdr,
                     cache.coverage, plan.has(Pass::AxisAlignedFilter) ? &filter : nullptr, &filtered,
                     &cache.filter_changes);
      out.occluded_samples = counts.occluded_samples;
      out.shaded_samples = counts.shaded_samples;
      out.interreflected_samples = counts.interreflected_samples;
      out.interreflection_rays = counts.interreflection_rays;
      out.sun_rays = counts.sun_rays;
      out.filtered_pixels = filtered.pixels;
      out.filter_taps = filtered.taps;
      // The filter runs inside the static shading; its time is its own pass's, not the shading's.
      if (plan.has(Pass::AxisAlignedFilter)) {
        t.subtract(filtered.ms);
        out.timings.push_back({Pass::AxisAlignedFilter, filtered.ms});
      } else if (lobe_filter_) {
        cache.filter_gate.skipped();
      }
    }
    if (layered) {
      PassTimer tl(out.timings, plan.has(Pass::Refraction) ? Pass::Refraction : Pass::Clearcoat);
      const LayerCounts counts = RefractionPass(scene_, ibl_, settings_, plan.internal_depth,
                                                plan.has(Pass::Refraction), plan.has(Pass::Clearcoat))
                                     .shade(cache.hits, view, cache.shading, cache.layers);
      composeLayeredStatic(cache.hits, cache.shading, cache.layers, cache.hdr);
      out.refraction_rays = counts.refraction_rays;
      out.refracted_samples = counts.refracted_samples;
      out.capped_paths = counts.capped_paths;
      out.supersampled_samples = counts.supersampled_samples;
      out.coated_samples = counts.coated_samples;
    }
    cache.plinth_pixels.clear();
    cache.shown.clear();
    if (plan.has(Pass::Plinth)) {
      PassTimer tp(out.timings, Pass::Plinth);
      drawPlinth(*plinth_light_, ibl_, view, cache.hits, cache.hdr, cache.plinth_pixels);
      std::set_union(cache.hits.covered.begin(), cache.hits.covered.end(), cache.plinth_pixels.begin(),
                     cache.plinth_pixels.end(), std::back_inserter(cache.shown));
    }
    cache.camera = view;
    cache.display_exposure = 0.0f;
    ++cache.static_version;
    cache.ready = true;
    cache.receivers_ready = false;
    if (refine) {
      cache.progress.restart(cache.bounces.pixels, cache.hdr, foreground);
      cache.refinement_gate.measuring();
    } else if (refines_) {
      cache.progress.stop();
      cache.refinement_gate.skipped();
    }
  } else if (refine) {
    PassTimer t(out.timings, Pass::ProgressiveRefinement);
    const AxisAlignedFilter filter;
    TracerSettings planned = settings_;
    planned.evaluation.sun_light = plan.sun_light;
    const RefinementStep step =
        cache.progress.advance(StaticShading(scene_, ibl_, planned, rough_map_.get(),
                                             plan.has(Pass::SelfOcclusion) ? visibility_.get() : nullptr,
                                             &lighting_, wide_lobes_.get()),
                               cache.hits, cache.camera, foreground, std::uint32_t(settings_.refinement_sets),
                               cache.shading, cache.walk_rays, cache.bounces.pixels, cache.hdr,
                               plan.has(Pass::AxisAlignedFilter) ? &filter : nullptr);
    // The filter's time is its own pass's, as in the static pass.
    if (step.filtered.ms > 0.0) {
      t.subtract(step.filtered.ms);
      out.timings.push_back({Pass::AxisAlignedFilter, step.filtered.ms});
    }
    out.filtered_pixels = step.filtered.pixels;
    out.filter_taps = step.filtered.taps;
    out.refinement_samples = step.samples;
    out.refinement_reset = step.reset;
    if (step.image_changed) cache.display_exposure = 0.0f;
    if (step.samples > 0 || step.image_changed) cache.receivers_ready = false;
    ++cache.static_version;
  }
  if (refines_) out.accumulated_sets = cache.progress.sets();
  if (fixed_exposure && cache.display_exposure != settings_.exposure) {
    PassTimer t(out.timings, Pass::ToneMap);
    cache.display = toneMapCovered(cache.hdr, plan.has(Pass::Plinth) ? cache.shown : cache.hits.covered,
                                   settings_.exposure);
    cache.display_exposure = settings_.exposure;
    ++cache.static_version;
  }
  const HitPointBuffer& hits = cache.hits;
  out.camera = cache.camera;
  out.refined_pixels = hits.refined.size();
  out.plinth_pixels = cache.plinth_pixels.size();
  out.coverage = cache.coverage;

  if (!plan.has(Pass::ForegroundWalk)) {
    out.hdr = cache.hdr;
    out.weight = cache.zero_weight;
  } else {
    // Scratch sized once; only the covered pixels' entries are written and read.
    hits.reservePerSample(cache.fg);
    cache.fg.resize(hits.hits.size());
    const ForegroundWalk walk(settings_, grid_, pyramids_, cameras, rough_map_.get());
    {
      PassTimer t(out.timings, Pass::ForegroundWalk);
      const WalkCounts counts = walk.walkView(hits, cache.walk_rays, cache.walk, cache.fg);
      out.walked_rays = counts.walked;
      out.foreground_hits = counts.found;
    }
    if (plan.has(Pass::RefractedForeground)) {
      PassTimer t(out.timings, Pass::RefractedForeground);
      out.refracted_walks = RefractionPass(scene_, ibl_, settings_, plan.internal_depth, true, false)
                                .walkTransmitted(hits, walk, cache.layers);
    }
    // Over the static images, only where some foreground was reached (the rest is the static
    // result already).
    PassTimer t(out.timings, Pass::Composition);
    const ComposedImages::Images composed = cache.composed.next(
        cache.hdr, fixed_exposure ? cache.display : cv::Mat(), cache.static_version, hits.covered);
    out.hdr = composed.hdr;
    out.weight = composed.weight;
    out.display = composed.display;
    out.composed_pixels =
        composeForeground(hits, cache.shading, cache.fg, fixed_exposure ? settings_.exposure : 0.0f, out.hdr,
                          out.weight, out.display, layered ? &cache.layers : nullptr);
  }
  if (plan.has(Pass::VisitorLight)) {
    PassTimer t(out.timings, Pass::VisitorLight);
    // Over a copy: the static image stays the cache's.
    if (!plan.has(Pass::ForegroundWalk)) out.hdr = cache.hdr.clone();
    if (!cache.receivers_ready) {
      cache.visitor_receivers = VisitorLight::receivers(hits, cache.shading, ibl_);
      cache.receivers_ready = true;
    }
    // At a fixed exposure the changed pixels' codes are written over the view's display so far (the
    // static one, or the composed one), which is the rest of the image tone-mapped already.
    if (fixed_exposure && out.display.empty()) out.display = cache.display.clone();
    out.visitor_lit_samples =
        visitor_light_->apply(cache.visitor_receivers, hits.width, out.hdr,
                              fixed_exposure ? &out.display : nullptr, settings_.exposure);
  }
  if (fixed_exposure) {
    out.exposure = settings_.exposure;
    if (out.display.empty()) out.display = cache.display;
  } else {
    PassTimer t(out.timings, Pass::ToneMap);
    out.exposure = autoExposure(out.hdr);
    out.display = toneMap(out.hdr, out.exposure);
  }
  if (!out.static_reused && plan.has(Pass::AxisAlignedFilter)) {
    // The filter's displayed change at the exposure the view is shown at.
    float codes = 0.0f;
    if (cache.filter_changes.size() == hits.pixelCount() && cache.bounces.pixels.size() == hits.pixelCount())
      for (const std::uint32_t p : hits.covered)
        if (cache.bounces.pixels[p].rough) {
          const FilterChange& c = cache.filter_changes[p];
          codes = std::max(codes, maxComponent(glm::abs(toneMapCodes(c.filtered, out.exposure) -
                                                        toneMapCodes(c.unfiltered, out.exposure))));
        }
    out.filter_codes = codes;
    cache.filter_gate.record(codes, view.position(), out.exposure, lightKey());
  }
  if (out.refinement_samples > 0 && !out.refinement_reset &&
      cache.progress.sets() ==
          std::min(ProgressiveAccumulation::kMeasuredSets, std::uint32_t(settings_.refinement_sets))) {
    // The refinement's displayed change at the exposure the view is shown at.
    out.refinement_codes = cache.progress.largestChange(cache.hdr, out.exposure);
    cache.refinement_gate.record(out.refinement_codes, view.position(), out.exposure, lightKey());
  }
  cache.shown_exposure = out.exposure;
  return out;
}

}  // namespace holo::reflect
