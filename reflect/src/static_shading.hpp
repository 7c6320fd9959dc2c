// The frame renderer's static pass (internal): per hit point of a view, the split-sum shading of
// the prefiltered IBL (psi_s's scale and environment, and the diffuse irradiance) with one
// interreflection bounce where the reflection meets the relic itself, and the ray the
// foreground walk follows from the point. What it writes depends on the relic, the hall and the
// eye only, so the frame renderer caches it per view (frame_renderer.hpp). Every surface is
// shaded by surface_shading.hpp (occlusion scales the reflected parts, emission is added to the
// diffuse part); a BLEND hit point is composited over the static shading of what is behind it.
//
// Self-occlusion: with the relic's visibility (relic_visibility.hpp), every relic surface's diffuse
// irradiance is its vertices' lit one instead of the unoccluded SH irradiance; the glTF occlusion texture
// then counts only where it is darker than the vertices' open share (its factor occlusion / openness, at most
// 1), so the two never darken twice.
//
// The sun: with TracerEvaluationKnobs::sun_light set (the effect plan's SunLight) and a sun in
// the panorama, a surface with a diffuse part is lit by the panorama without its sun (the SH
// irradiance, or the visibility's lighting where it was lit without the sun) plus the sun as a
// directional light with a shadow ray (sun_light.hpp).
//
// Interreflection: a material below rough_interreflection_roughness (and not read from the rough
// map) follows its mirror ray; where that meets the relic, the point's environment becomes the
// second point's (its specular scale multiplied in, its diffuse added) and the walk starts there.
// A rougher one traces its GGX lobe at a point in each of rough_interreflection_grid^2 strata
// instead (hashed per pixel and sample, or the centres: evaluation.lobe_strata_jittered): the
// share that meets the relic sees the second points' static shading (a blur of them as wide as
// the lobe), the rest the hall; a second point that reflects follows its own mirror ray, and
// where that meets the relic again shows that point's static shading and what its mirror ray
// meets in turn, up to rough_interreflection_mirror_bounces points, instead of the hall (inside a
// bowl the light goes round); its walk keeps the first point's mirror ray. The
// hall's share is the prefiltered environment of the whole lobe scaled by the share of its light
// that comes from the open samples' directions (each sample reads the environment prefiltered to
// its stratum, FIS Section 5.2): the lobe's own visibility, weighted by where the hall's light
// is, not by the count of open samples alone (a bright window the bowl's rim hides is not
// reflected at the open share of its brightness). The glTF occlusion texture then counts only
// where it is darker than the lobe's open share, so the two never darken the specular twice. Interleaved,
// each hit point traces only the strata of its 2x2 pixel class dealt to its sample, and a 3x3 tent over the
// pixels of the same surface sums them all; with an axis-aligned filter (axis_aligned_filter.hpp) the
// tent's sums are filtered further, as wide as the lobe's bandwidth and the distance to what it meets allow.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/relic_visibility.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/rough_foreground_map.hpp"
#include "holo/reflect/tracer_settings.hpp"
#include "lobe_bounce.hpp"
#include "sun_light.hpp"
#include "walk_ray.hpp"

namespace holo::reflect {

class AxisAlignedFilter;
class WideLobeCache;
struct FilterCounts;
struct FilterChange;

// What a shade() call did, for the statistics.
struct StaticCounts {
  std::uint64_t shaded_samples = 0;    // valid samples shaded
  std::uint64_t occluded_samples = 0;  // those whose diffuse light the visibility occluded
  // Those that cast at least one interreflection ray, and the rays (mirror, lobe strata and the
  // lobe's second bounces) cast against the relic.
  std::uint64_t interreflected_samples = 0, interreflection_rays = 0;
  std::uint64_t sun_rays = 0;  // the sun light's shadow rays (sun_light.hpp; 0 with it off)
  void add(const StaticCounts& other);
};

class StaticShading {
 public:
  // Everything must outlive this; rough_map may be null (no material reads it), visibility null
  // (no self-occlusion), else with its lighting under `ibl` (RelicVisibility::lit).
  // wide_lobes (may be null): the widest lobes' interreflection read from it (wide_lobe_cache.hpp)
  // instead of traced per sample, its missing entries traced by this shading.
  StaticShading(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                const RoughForegroundMap* rough_map, const RelicVisibility* visibility = nullptr,
                const RelicVisibility::Lighting* lighting = nullptr,
                const WideLobeCache* wide_lobes = nullptr);

  // Shades every valid sample of `hits` (traced from `view`) into shading and walk_rays (per
  // entry of hits.hits; others are left as they were) and writes the static image: hdr, CV_32FC3
  // linear BGR, the mean over each pixel's samples of psi_s + diffuse (misses black), and
  // coverage, CV_32FC1; both must be view-sized and zero, only covered pixels are written.
  // `bounces` is kept across calls (lobe_bounce.hpp); its pixels are what the progressive refinement
  // and the filter read. With `filter` (may be null) the rough lobe's pooled
  // interreflection is filtered and `filter_counts` (then not null) receives its counters; with
  // `filter_changes` (may be null) too, it is sized to the view's pixels and each filtered pixel's
  // radiance without and with the filter is written there (the other entries are left as they
  // were). The interreflection runs where settings.relic_interreflection is on and casts no ray that the
  // relic's supporting planes prove a miss (RenderScene::mayMeetRelicAgain).
  StaticCounts shade(const HitPointBuffer& hits, const CameraModel& view,
                     std::vector<SplitSumShading>& shading, std::vector<WalkRay>& walk_rays,
                     ViewBounces& bounces, cv::Mat& hdr, cv::Mat& coverage,
                     const AxisAlignedFilter* filter = nullptr, FilterCounts* filter_counts = nullptr,
                     std::vector<FilterChange>* filter_changes = nullptr) const;

  // Where a sample (pixel index, sample within the pixel) takes its lobe's strata: an offset in
  // [0, 1)^2 within each stratum; shade() takes sample set 0's (progressive_accumulation.hpp), or
  // the centres (0.5, 0.5) where lobe_strata_jittered is off.
  using StratumOffset = std::function<vec2(std::size_t pixel, int sample)>;
  // Another sample set of the rough interreflection (progressive_accumulation.hpp), after shade()
  // with the same hits, view and buffers: each valid sample of `pixels` whose material traces its
  // lobe is shaded again with its strata at `offset`, its lobe samples added to
  // accumulated[pixel] (the sums of the sets so far; shade()'s `bounces.pixels`); then each of those
  // pixels pools its neighbours' accumulated sums (filtered with `filter` as shade() does; then
  // filter_counts is not null) and its samples' shading and hdr pixel are written again. The
  // interleaved strata only (rough_interreflection_interleaved). Returns the samples shaded.
  std::uint64_t reshadeLobes(const HitPointBuffer& hits, const CameraModel& view,
                             const std::vector<std::uint32_t>& pixels, const StratumOffset& offset,
                             std::vector<SplitSumShading>& shading, std::vector<WalkRay>& walk_rays,
                             std::vector<PixelBounce>& accumulated, cv::Mat& hdr,
                             const AxisAlignedFilter* filter = nullptr,
                             FilterCounts* filter_counts = nullptr) const;
  // Some relic material traces its lobe's strata per sample for the interreflection (not read
  // from the wide lobes' cache).
  bool tracesLobes() const { return lobe_materials_; }

 private:
  // Which of the rough lobe's strata a hit point traces: its pixel's 2x2 class ((x & 1) +
  // 2 (y & 1)) and its sample of the pixel's.
  // With the footprint of the hit point's pixel: cone_width (metres at the hit) grows by
  // spread (radians) per metre a secondary ray travels.
  // stratum_offset: where within each of its strata the sample takes its lobe sample.
  struct LobeShare {
    int pixel_class = 0, sample = 0, samples = 1;
    float cone_width = 0.0f, spread = 0.0f;
    vec2 stratum_offset{0.5f};
  };
  static LobeShare pixelLobeShare(const HitPointBuffer& hits, std::size_t p, float spread);
  // The relic rays a block of samples leaves to be cast together in packets, and where each one's
  // hit goes: a sample's mirror ray, or its lobe's strata in the order it traces them (a stratum
  // the supporting planes prove a miss casts none), so that the sums come out as one ray at a
  // time gives them.
  struct DeferredRays {
    struct Mirror {
      std::size_t sample;
      LobeShare share;
      std::uint32_t ray;
    };
    struct Stratum {
      vec3 hall;         // the hall's prefiltered radiance along it
      std::int64_t ray;  // -1: not cast (the planes prove a miss)
    };
    struct Lobe {
      std::size_t pixel, sample;
      LobeShare share;
      LobeBounce bounce;  // above and hall summed; the rest is summed from the hits
      std::size_t first_stratum, strata;
    };
    std::vector<Ray> rays;
    std::vector<RayHit> hits;
    std::vector<Mirror> mirrors;
    std::vector<Stratum> strata;
    std::vector<Lobe> lobes;
    std::uint64_t samples_casting = 0;  // samples that deferred at least one ray
    void clear();
  };
  // One hit point (sample `i` of pixel `pixel`): its shading and walk ray; its interreflection
  // rays are deferred to `deferred` (finishDeferred casts them and completes the shading).
  void shadeHit(const HitPoint& hp, std::size_t pixel, std::size_t i, const LobeShare& share,
                SplitSumShading& shading, WalkRay& walk_ray, DeferredRays& deferred) const;
  // Casts the deferred rays in packets and completes each deferred sample's shading and walk ray
  // (of hits.hits[sample]). For a material read from the rough map with interleaved strata, its
  // share of the lobe's interreflection is handed to `pool(pixel, sample, bounce)` for the pixel pooling
  // instead. Returns the rays cast (mirror, strata and the lobe's second bounces).
  std::uint64_t finishDeferred(
      const HitPointBuffer& hits, DeferredRays& deferred, std::vector<SplitSumShading>& shading,
      std::vector<WalkRay>& walk_rays,
      const std::function<void(std::size_t, std::size_t, const LobeBounce&)>& pool) const;
  // BLEND: the hit point's shading composited over the static shading of what is behind it.
  void compositeBehind(const HitPoint& hp, const LobeShare& share, SplitSumShading& shading) const;
  // The lobe's strata of one hit point: their hall sums and rays, deferred.
  void deferLobeBounce(const HitPoint& hp, std::size_t pixel, std::size_t i, const LobeShare& share,
                       DeferredRays& deferred) const;
  // What a lobe sample's second point (`surface`, met by `ray` at `hit`, shaded `second`)
  // reflects: the hall, or where its mirror ray meets the relic again, that point's shading and
  // what it reflects in turn, up to rough_interreflection_mirror_bounces points.
  vec3 secondEnvironment(const SurfacePoint& surface, const Ray& ray, const RayHit& hit,
                         const SplitSumShading& second, const LobeShare& share, std::uint64_t& rays) const;
  // Whether a material this rough traces its lobe's strata for the interreflection.
  bool tracesLobe(float roughness) const;
  // Whether the hit point traces its lobe's strata itself (tracesLobe, not read from the cache).
  bool samplesLobe(const HitPoint& hp) const;
  // Whether the hit point reads its lobe from the wide lobes' cache.
  bool readsWideLobe(const HitPoint& hp) const;
  // A wide lobe cache entry: every stratum of the lobe of a material `roughness` rough at
  // `position` (unit `normal`) for the eye along `to_viewer`, traced at once.
  LobeBounce traceWholeLobe(const vec3& position, const vec3& normal, const vec3& to_viewer,
                            float roughness) const;
  // The factor the occlusion texture puts on a surface's reflected light: beyond the visibility's
  // open share where the visibility covers it, the texture's own occlusion elsewhere.
  float textureOcclusion(const SurfacePoint& surface) const;
  // surface_shading.hpp's shadeSurface, with the visibility's irradiance where it covers the point.
  SplitSumShading shadeAt(const SurfacePoint& surface, const vec3& wo) const;
  // A relic surface a secondary ray (a mirror ray, a lobe's stratum) meets, seen from the ray's
  // origin: shadeAt, where it transmits with the light traced through the glass (bent, what
  // stands inside shaded: glass_transport.hpp's lightThroughGlass) in place of the diffuse share
  // it transmits. `rays` counts the transmitted path's Embree rays.
  SplitSumShading shadeMet(const SurfacePoint& surface, const Ray& ray, std::uint64_t& rays) const;
  // Adds to `bounce` a lobe stratum's ray that met the relic's `surface` at `hit`: its shading
  // (shadeMet) and what it reflects (secondEnvironment). `rays` counts the rays these cast.
  void addMetStratum(LobeBounce& bounce, const SurfacePoint& surface, const Ray& ray, const RayHit& hit,
                     const LobeShare& share, std::uint64_t& rays) const;
  // The 3x3 tent's sum of the pixel's and its same-surface neighbours' lobe samples.
  LobeBounce poolLobeBounces(const std::vector<PixelBounce>& bounces, int width, int height,
                             const CameraModel& view, int x, int y) const;

  const RenderScene& scene_;
  const PrefilteredIbl& ibl_;
  const TracerSettings& settings_;
  const RoughForegroundMap* rough_map_;
  const RelicVisibility* visibility_;
  const RelicVisibility::Lighting* lighting_;
  const WideLobeCache* wide_lobes_;
  std::optional<SunLight> sun_;
  mutable tbb::enumerable_thread_specific<std::uint64_t> sun_rays_;
  mutable tbb::enumerable_thread_specific<std::uint64_t> wide_lobe_rays_;  // tracing cache entries
  bool lobe_materials_ = false;  // some relic material traces its lobe (tracesLobe)
};

}  // namespace holo::reflect
