#include "static_shading.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "axis_aligned_filter.hpp"
#include "compose_pass.hpp"
#include "glass_transport.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "layer_inputs.hpp"
#include "lobe_effect_gate.hpp"
#include "lobe_sample_sets.hpp"
#include "wide_lobe_cache.hpp"

namespace holo::reflect {
namespace {

// The stratum points (the u of ggx::sampleVisibleNormal) of a side x side grid over the lobe
// that one hit point traces, each at `offset` within its stratum ((0.5, 0.5): the centres; other
// offsets are the further sample sets of progressive_accumulation.hpp). Interleaved: the 2x2 pixel classes
// take every other stratum in each direction (each class alone a coarse grid over the whole lobe), dealt
// round-robin to the pixel's samples; a 3x3 tent over the pixels then sums every stratum with equal weight.
template <class F>
void forEachLobeStratum(int side, bool interleaved, int pixel_class, int sample, int samples, vec2 offset,
                        F&& f) {
  const auto centre = [&](int i, int j) {
    f(vec2((float(i) + offset.x) / float(side), (float(j) + offset.y) / float(side)));
  };
  if (!interleaved) {
    for (int k = 0; k < side * side; ++k) centre(k % side, k / side);
    return;
  }
  const int half = side / 2, count = half * half;
  const auto own = [&](int r) {
    centre(2 * (r % half) + (pixel_class & 1), 2 * (r / half) + (pixel_class >> 1));
  };
  if (count <= samples) {
    own(sample % count);
    return;
  }
  for (int r = sample; r < count; r += samples) own(r);
}

// The solid angle of a lobe sample's prefiltered lookup over its stratum's own: filtered
// importance sampling's Omega_s = 1 / (N pdf) with half its bias of one level towards blur. Wider
// lookups blur the hall seen through the lobe's open share (a window or a sun the rim half hides
// reads as if it were not hidden: the metal bowl's inside too bright); narrower ones leave each
// pixel's few strata noisier where the tent and the axis-aligned filter pool them (measured at 1,
// 2 and 4: docs/tracer/self_occlusion.md).
constexpr float kLobeStratumOverlap = 2.0f;

// The perceptual roughness whose GGX lobe (4 pi alpha^2 about the reflected direction) covers
// kLobeStratumOverlap times a stratum of the visible-normal sampling, 1 / (strata pdf), with
// pdf = G1(wo) D(h) / (4 wo.z) the reflected direction's density (wo, h local, wo.z > 0).
float stratumRoughness(const vec3& wo, const vec3& h, float alpha, int strata) {
  const float pdf = ggx::G1(wo.z, alpha) * ggx::D(h.z, alpha) / (4.0f * wo.z);
  if (!(pdf > 0.0f)) return 1.0f;
  const float stratum_alpha = std::sqrt(kLobeStratumOverlap / (float(strata) * pdf) / (4.0f * kPi));
  return std::min(std::sqrt(stratum_alpha), 1.0f);
}

// `texture_occlusion`: the factor the occlusion texture put on shading.specular_scale;
// `weighted`: the hall's share weighted by its light (else by the open count).
void addLobeBounce(const LobeBounce& bounce, float texture_occlusion, bool weighted,
                   SplitSumShading& shading) {
  if (!(bounce.above > 0.0f)) return;
  const float fraction = std::min(bounce.met / bounce.above, 1.0f);
  // The texture beyond the lobe's own open share (the traced samples already hold the relic's
  // occlusion of the lobe).
  if (fraction > 0.0f && texture_occlusion > 0.0f && texture_occlusion < 1.0f)
    shading.specular_scale *= std::min(1.0f, texture_occlusion / (1.0f - fraction)) / texture_occlusion;
  // The hall seen through the lobe's open directions: the whole lobe's prefiltered light scaled
  // by the open samples' share of it (per channel; by the open count where the hall is black).
  vec3 open_share(1.0f - fraction);
  for (int c = 0; c < 3; ++c)
    if (weighted && bounce.hall[c] > 0.0f) open_share[c] = std::min(bounce.open[c] / bounce.hall[c], 1.0f);
  shading.environment *= open_share;
  if (!(bounce.met > 0.0f)) return;
  // The share of the lobe that meets the relic sees its second points' static shading (their own
  // foreground is left out: the rough map read at the first point stands for the whole lobe).
  shading.diffuse += shading.specular_scale * fraction * bounce.diffuse / bounce.met;
  shading.environment += fraction * bounce.specular / bounce.met;
}

SurfacePoint surfaceOf(const HitPoint& hp) {
  SurfacePoint s;
  s.position = hp.position;
  s.normal = hp.normal;
  s.clearcoat_normal = hp.clearcoat_normal;
  s.material = hp.material;
  s.emission = hp.emission;
  s.occlusion = hp.occlusion;
  s.alpha = hp.alpha;
  s.location = hp.location;
  return s;
}

}  // namespace

void StaticCounts::add(const StaticCounts& other) {
  shaded_samples += other.shaded_samples;
  occluded_samples += other.occluded_samples;
  interreflected_samples += other.interreflected_samples;
  interreflection_rays += other.interreflection_rays;
  sun_rays += other.sun_rays;
}

StaticShading::StaticShading(const RenderScene& scene, const PrefilteredIbl& ibl,
                             const TracerSettings& settings, const RoughForegroundMap* rough_map,
                             const RelicVisibility* visibility, const RelicVisibility::Lighting* lighting,
                             const WideLobeCache* wide_lobes)
    : scene_(scene),
      ibl_(ibl),
      settings_(settings),
      rough_map_(rough_map),
      visibility_(lighting ? visibility : nullptr),
      lighting_(lighting),
      wide_lobes_(wide_lobes && wide_lobes->active() ? wide_lobes : nullptr) {
  // A mesh whose lobe the cache holds samples none itself.
  const Model& relic = scene_.relic();
  for (std::size_t m = 0; m < relic.meshes.size(); ++m) {
    const int index = relic.meshes[m].material;
    if (wide_lobes_ && wide_lobes_->coversMesh(m)) continue;
    if (const auto& material = scene_.relicMaterialOverride())
      lobe_materials_ = lobe_materials_ || tracesLobe(material->roughness);
    else if (index < 0 || std::size_t(index) >= relic.materials.size())
      lobe_materials_ = lobe_materials_ || tracesLobe(Material{}.roughness);
    else
      lobe_materials_ = lobe_materials_ ||
                        relic.materials[std::size_t(index)].metallic_roughness_texture.used() ||
                        tracesLobe(relic.materials[std::size_t(index)].roughness);
  }
  if (settings_.evaluation.sun_light && ibl_.sun().found) sun_.emplace(scene_, ibl_, settings_);
}

bool StaticShading::tracesLobe(float roughness) const {
  return settings_.rough_interreflection_grid > 1 && (readsRoughMap(rough_map_, settings_, roughness) ||
                                                      roughness >= settings_.rough_interreflection_roughness);
}

bool StaticShading::readsWideLobe(const HitPoint& hp) const {
  return wide_lobes_ && tracesLobe(hp.material.roughness) && wide_lobes_->covers(hp.location);
}

bool StaticShading::samplesLobe(const HitPoint& hp) const {
  return tracesLobe(hp.material.roughness) && !readsWideLobe(hp);
}

LobeBounce StaticShading::traceWholeLobe(const vec3& position, const vec3& normal, const vec3& to_viewer,
                                         float roughness) const {
  LobeBounce bounce;
  const Frame frame(normal);
  const vec3 wo = frame.toLocal(to_viewer);
  if (!(wo.z > 0.0f)) return bounce;
  const float alpha = std::max(roughness * roughness, 1e-3f);
  const int side = settings_.rough_interreflection_grid, strata = side * side;
  const RayScene& relic = scene_.relicOnly();
  const LobeShare share;  // the vertex's sharpest texture footprint
  std::uint64_t rays = 0;
  forEachLobeStratum(side, false, 0, 0, 1, vec2(0.5f), [&](const vec2& u) {
    const vec3 h = ggx::sampleVisibleNormal(wo, alpha, u);
    const vec3 l = glm::reflect(-to_viewer, frame.toWorld(h));
    if (!(glm::dot(l, normal) > 0.0f)) return;
    bounce.above += 1.0f;
    const vec3 hall = ibl_.seenFrom(position, l, stratumRoughness(wo, h, alpha, strata));
    if (isFinite(hall)) bounce.hall += hall;
    const Ray ray{position + normal * settings_.ray_offset, l};
    const RayHit hit = relic.intersect(ray);
    ++rays;
    if (!hit.hit()) {
      if (isFinite(hall)) bounce.open += hall;
      return;
    }
    const SurfacePoint surface = resolveSurface(scene_, relic, ray, hit, 0.0f);
    if (isFinite(surface.normal)) addMetStratum(bounce, surface, ray, hit, share, rays);
  });
  wide_lobe_rays_.local() += rays;
  return bounce;
}

void StaticShading::addMetStratum(LobeBounce& bounce, const SurfacePoint& surface, const Ray& ray,
                                  const RayHit& hit, const LobeShare& share, std::uint64_t& rays) const {
  const SplitSumShading second = shadeMet(surface, ray, rays);
  bounce.diffuse += second.diffuse;
  bounce.specular += second.specular_scale * secondEnvironment(surface, ray, hit, second, share, rays);
  bounce.met += 1.0f;
  bounce.nearest = std::min(bounce.nearest, hit.t);
}

float StaticShading::textureOcclusion(const SurfacePoint& surface) const {
  if (!visibility_ || !visibility_->covers(surface.location)) return surface.occlusion;
  return std::min(1.0f, surface.occlusion / std::max(visibility_->openness(surface.location), 1e-3f));
}

SplitSumShading StaticShading::shadeMet(const SurfacePoint& surface, const Ray& ray,
                                        std::uint64_t& rays) const {
  SplitSumShading parts = shadeAt(surface, -ray.direction);
  const SurfaceMaterial& m = surface.material;
  const float share = (1.0f - clamp01(m.metallic)) * clamp01(m.transmission);
  if (!(share > 0.0f)) return parts;
  const vec3 through = lightThroughGlass(scene_, ibl_, settings_, surface, ray.direction, rays);
  const vec3 reflected_light = parts.diffuse - surface.emission;
  parts.diffuse = (1.0f - share) * reflected_light + surface.emission + through;
  return parts;
}

SplitSumShading StaticShading::shadeAt(const SurfacePoint& surface, const vec3& wo) const {
  const bool covered = visibility_ && visibility_->covers(surface.location);
  if (!covered && !sun_) return shadeSurface(ibl_, surface, wo);
  // The visibility's lighting holds the sun unless it was lit without it.
  const bool sun_apart = sun_ && (!covered || lighting_->without_sun);
  vec3 irradiance = covered     ? visibility_->irradiance(*lighting_, surface.location)
                    : sun_apart ? ibl_.irradianceWithoutSun(surface.normal)
                                : ibl_.irradiance(surface.normal);
  if (sun_apart) {
    // Only a diffuse part shows the sun's shadow: elsewhere the irradiance is not read.
    std::uint32_t rays = 0;
    irradiance +=
        readsSunIrradiance(surface.material)
            ? sun_->irradiance(surface, wo, rays)
            : ibl_.sun().power * std::max(glm::dot(surface.normal, ibl_.relicFrameSunDirection()), 0.0f);
    if (rays > 0) sun_rays_.local() += rays;
  }
  SplitSumShading parts = ibl_.shadeParts(surface.material, surface.normal, wo,
                                          glm::reflect(-wo, surface.normal), surface.position, &irradiance);
  // The texture's occlusion beyond what the vertices' visibility already holds.
  const float beyond = textureOcclusion(surface);
  parts.specular_scale *= beyond;
  parts.diffuse = beyond * parts.diffuse + surface.emission;
  return parts;
}

void StaticShading::DeferredRays::clear() {
  rays.clear();
  hits.clear();
  mirrors.clear();
  strata.clear();
  lobes.clear();
  samples_casting = 0;
}

void StaticShading::shadeHit(const HitPoint& hp, std::size_t pixel, std::size_t i, const LobeShare& share,
                             SplitSumShading& shading, WalkRay& walk_ray, DeferredRays& deferred) const {
  shading = shadeAt(surfaceOf(hp), hp.to_viewer);
  walk_ray = {hp.position, hp.normal, hp.reflected, hp.material.roughness, false};
  if (hp.alpha < 1.0f) compositeBehind(hp, share, shading);
  if (!settings_.relic_interreflection) return;
  if (readsWideLobe(hp)) {
    const float roughness = hp.material.roughness;
    const LobeBounce bounce = wide_lobes_->lookup(
        hp.location, hp.to_viewer, [&](const vec3& position, const vec3& normal, const vec3& eye) {
          return traceWholeLobe(position, normal, eye, roughness);
        });
    addLobeBounce(bounce, textureOcclusion(surfaceOf(hp)), settings_.evaluation.lobe_visibility, shading);
    return;
  }
  if (tracesLobe(hp.material.roughness)) {
    deferLobeBounce(hp, pixel, i, share, deferred);
    return;
  }
  if (!hp.mirror_may_meet_relic) return;  // a ray it need not cast: it would miss
  deferred.mirrors.push_back({i, share, std::uint32_t(deferred.rays.size())});
  deferred.rays.push_back({hp.position + hp.normal * settings_.ray_offset, hp.reflected});
  ++deferred.samples_casting;
}

std::uint64_t StaticShading::finishDeferred(
    const HitPointBuffer& hits, DeferredRays& deferred, std::vector<SplitSumShading>& shading,
    std::vector<WalkRay>& walk_rays,
    const std::function<void(std::size_t, std::size_t, const LobeBounce&)>& pool) const {
  const RayScene& relic = scene_.relicOnly();
  deferred.hits.resize(deferred.rays.size());
  // A block's mirror rays and a point's lobe strata start close together, but a curved relic fans
  // their directions out, so they are not flagged coherent (that flag is for primary rays).
  relic.intersectPackets(deferred.rays, deferred.hits, RayCoherence::Incoherent);
  std::uint64_t rays = deferred.rays.size();
  for (const DeferredRays::Mirror& mirror : deferred.mirrors) {
    const HitPoint& hp = hits.hits[mirror.sample];
    const Ray& ray = deferred.rays[mirror.ray];
    const RayHit& hit = deferred.hits[mirror.ray];
    if (!hit.hit()) continue;
    const SurfacePoint surface =
        resolveSurface(scene_, relic, ray, hit, mirror.share.cone_width + hit.t * mirror.share.spread);
    const vec3 position = surface.position;
    const vec3 normal = surface.normal;
    const vec3 reflected = glm::reflect(ray.direction, normal);
    if (!isFinite(position) || !isFinite(normal) || !isFinite(reflected)) continue;
    const SurfaceMaterial& material = surface.material;
    const SplitSumShading second = shadeMet(surface, ray, rays);
    // L = diffuse_1 + s_1 L_2 and L_2 = diffuse_2 + s_2 (psi_d w + env_2 (1 - w)): the composition's
    // form with scale s_1 s_2 and environment env_2.
    SplitSumShading& first = shading[mirror.sample];
    first.diffuse += first.specular_scale * second.diffuse;
    first.specular_scale *= second.specular_scale;
    first.environment = second.environment;
    // The two lobes widen each other: GGX alphas (roughness^2) add in quadrature.
    const float a1 = hp.material.roughness * hp.material.roughness,
                a2 = material.roughness * material.roughness;
    walk_rays[mirror.sample] = {position, normal, reflected, std::sqrt(std::sqrt(a1 * a1 + a2 * a2)), true};
  }
  for (DeferredRays::Lobe& lobe : deferred.lobes) {
    LobeBounce& bounce = lobe.bounce;
    const LobeShare& share = lobe.share;
    for (std::size_t k = lobe.first_stratum; k < lobe.first_stratum + lobe.strata; ++k) {
      const DeferredRays::Stratum& stratum = deferred.strata[k];
      // A stratum the supporting planes prove a miss counts as one: it sees the hall.
      if (stratum.ray < 0 || !deferred.hits[std::size_t(stratum.ray)].hit()) {
        if (isFinite(stratum.hall)) bounce.open += stratum.hall;
        continue;
      }
      const Ray& ray = deferred.rays[std::size_t(stratum.ray)];
      const RayHit& hit = deferred.hits[std::size_t(stratum.ray)];
      const SurfacePoint surface =
          resolveSurface(scene_, relic, ray, hit, share.cone_width + hit.t * share.spread);
      if (isFinite(surface.normal)) addMetStratum(bounce, surface, ray, hit, share, rays);
    }
    if (settings_.evaluation.rough_interreflection_interleaved) {
      pool(lobe.pixel, lobe.sample, bounce);
      continue;
    }
    addLobeBounce(bounce, textureOcclusion(surfaceOf(hits.hits[lobe.sample])),
                  settings_.evaluation.lobe_visibility, shading[lobe.sample]);
  }
  return rays;
}

void StaticShading::compositeBehind(const HitPoint& hp, const LobeShare& share,
                                    SplitSumShading& shading) const {
  // What is behind: the next relic surface along the primary ray (its static shading; layers
  // further back by stochastic transparency) or the pyramid's black background.
  const RayScene& relic = scene_.relicOnly();
  const Ray ray{hp.position - hp.to_viewer * settings_.ray_offset, -hp.to_viewer};
  vec3 behind(0.0f);
  const RayHit hit = relic.intersect(ray);
  if (hit.hit()) {
    const SurfacePoint surface =
        resolveSurface(scene_, relic, ray, hit, share.cone_width + hit.t * share.spread);
    const SplitSumShading parts = shadeAt(surface, -ray.direction);
    behind = parts.specular_scale * parts.environment + parts.diffuse;
    if (!isFinite(behind)) behind = vec3(0.0f);
  }
  const float a = hp.alpha;
  shading.specular_scale *= a;
  shading.diffuse = a * shading.diffuse + (1.0f - a) * behind;
}

vec3 StaticShading::secondEnvironment(const SurfacePoint& surface, const Ray& ray, const RayHit& hit,
                                      const SplitSumShading& second, const LobeShare& share,
                                      std::uint64_t& rays) const {
  // L_k = diffuse_k + s_k L_(k+1) along the mirror rays: what each point adds and the product of
  // the specular scales before it; the last point's hall is read as if its lobe were open.
  const RayScene& relic = scene_.relicOnly();
  SurfacePoint at = surface;
  Ray in = ray;
  RayHit met = hit;
  SplitSumShading shaded = second;
  float travelled = hit.t;
  vec3 added(0.0f), scale(1.0f);
  for (int bounce = 0; bounce < settings_.rough_interreflection_mirror_bounces; ++bounce) {
    if (!(maxComponent(shaded.specular_scale) > 0.0f)) break;
    const vec3 reflected = glm::reflect(in.direction, at.normal);
    if (!scene_.mayMeetRelicAgain(met, reflected)) break;
    const Ray next{at.position + at.normal * settings_.ray_offset, reflected};
    const RayHit next_hit = relic.intersect(next);
    ++rays;
    if (!next_hit.hit()) break;
    travelled += next_hit.t;
    const SurfacePoint next_surface =
        resolveSurface(scene_, relic, next, next_hit, share.cone_width + travelled * share.spread);
    if (!isFinite(next_surface.normal)) break;
    const SplitSumShading next_shaded = shadeMet(next_surface, next, rays);
    if (!isFinite(next_shaded.diffuse) || !isFinite(next_shaded.specular_scale)) break;
    added += scale * next_shaded.diffuse;
    scale *= next_shaded.specular_scale;
    at = next_surface;
    in = next;
    met = next_hit;
    shaded = next_shaded;
  }
  const vec3 seen = added + scale * shaded.environment;
  return isFinite(seen) ? seen : second.environment;
}

void StaticShading::deferLobeBounce(const HitPoint& hp, std::size_t pixel, std::size_t i,
                                    const LobeShare& share, DeferredRays& deferred) const {
  DeferredRays::Lobe lobe{pixel, i, share, LobeBounce{}, deferred.strata.size(), 0};
  const Frame frame(hp.normal);
  const vec3 wo = frame.toLocal(hp.to_viewer);
  if (!(wo.z > 0.0f)) {
    deferred.lobes.push_back(lobe);
    return;
  }
  const float alpha = std::max(hp.material.roughness * hp.material.roughness, 1e-3f);
  const int strata = settings_.rough_interreflection_grid * settings_.rough_interreflection_grid;
  const std::size_t first_ray = deferred.rays.size();
  forEachLobeStratum(
      settings_.rough_interreflection_grid, settings_.evaluation.rough_interreflection_interleaved,
      share.pixel_class, share.sample, share.samples, share.stratum_offset, [&](const vec2& u) {
        const vec3 h = ggx::sampleVisibleNormal(wo, alpha, u);
        const vec3 l = glm::reflect(-hp.to_viewer, frame.toWorld(h));
        if (!(glm::dot(l, hp.normal) > 0.0f)) return;
        lobe.bounce.above += 1.0f;
        const vec3 hall = ibl_.seenFrom(hp.position, l, stratumRoughness(wo, h, alpha, strata));
        if (isFinite(hall)) lobe.bounce.hall += hall;
        ++lobe.strata;
        if (hp.location.located() &&
            !scene_.mayMeetRelicAgain(hp.location.mesh, hp.location.triangle, hp.location.front, l)) {
          deferred.strata.push_back({hall, -1});
          return;
        }
        deferred.strata.push_back({hall, std::int64_t(deferred.rays.size())});
        deferred.rays.push_back({hp.position + hp.normal * settings_.ray_offset, l});
      });
  if (deferred.rays.size() > first_ray) ++deferred.samples_casting;
  deferred.lobes.push_back(lobe);
}

LobeBounce StaticShading::poolLobeBounces(const std::vector<PixelBounce>& bounces, int width, int height,
                                          const CameraModel& view, int x, int y) const {
  const PixelBounce& own = bounces[std::size_t(y) * std::size_t(width) + std::size_t(x)];
  // Neighbours on the same surface only: a few pixels' footprint away and facing alike.
  const float reach = 4.0f * glm::length(own.position - view.position()) / view.intrinsics().fx;
  LobeBounce sum;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      const PixelBounce& other = bounces[std::size_t(ny) * std::size_t(width) + std::size_t(nx)];
      if (!other.rough || glm::dot(other.normal, own.normal) < 0.9f ||
          glm::length(other.position - own.position) > reach)
        continue;
      sum.add(other.samples, float((2 - std::abs(dx)) * (2 - std::abs(dy))));
    }
  return sum;
}

// Pixel p's share of the lobe strata: its class in the 2x2 interleaving, its sample count and
// the footprint's growth (radians per pixel); the sample, cone and offset are set per sample.
StaticShading::LobeShare StaticShading::pixelLobeShare(const HitPointBuffer& hits, std::size_t p,
                                                       float spread) {
  const std::size_t w = std::size_t(hits.width);
  const int x = int(p % w), y = int(p / w);
  LobeShare share{(x & 1) + 2 * (y & 1), 0, hits.sampleCount(p)};
  share.spread = spread;
  return share;
}

std::uint64_t StaticShading::reshadeLobes(const HitPointBuffer& hits, const CameraModel& view,
                                          const std::vector<std::uint32_t>& pixels,
                                          const StratumOffset& offset, std::vector<SplitSumShading>& shading,
                                          std::vector<WalkRay>& walk_rays,
                                          std::vector<PixelBounce>& accumulated, cv::Mat& hdr,
                                          const AxisAlignedFilter* filter,
                                          FilterCounts* filter_counts) const {
  const int w = hits.width;
  const float spread = 1.0f / view.intrinsics().fx;
  std::atomic<std::uint64_t> reshaded{0};
  tbb::enumerable_thread_specific<DeferredRays> deferred_rays;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::uint64_t count = 0;
                      DeferredRays& deferred = deferred_rays.local();
                      deferred.clear();
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t p = pixels[k];
                        const std::size_t first = hits.firstSample(p);
                        LobeShare share = pixelLobeShare(hits, p, spread);
                        for (share.sample = 0; share.sample < share.samples; ++share.sample) {
                          const std::size_t i = first + std::size_t(share.sample);
                          if (!hits.valid[i] || !samplesLobe(hits.hits[i])) continue;
                          share.cone_width = glm::length(hits.hits[i].position - view.position()) * spread;
                          share.stratum_offset = offset(p, share.sample);
                          shadeHit(hits.hits[i], p, i, share, shading[i], walk_rays[i], deferred);
                          ++count;
                        }
                      }
                      finishDeferred(hits, deferred, shading, walk_rays,
                                     [&](std::size_t p, std::size_t, const LobeBounce& bounce) {
                                       accumulated[p].samples.add(bounce, 1.0f);
                                     });
                      reshaded += count;
                    });
  // Pooled and filtered as shade() does, from the accumulated sums.
  std::vector<LobeBounce> pooled(hits.pixelCount());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t p = pixels[k];
                        pooled[p] = poolLobeBounces(accumulated, w, hits.height, view,
                                                    int(p % std::size_t(w)), int(p / std::size_t(w)));
                      }
                    });
  if (filter) *filter_counts = filter->apply(accumulated, pooled, w, hits.height, view);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t p = pixels[k];
                        const std::size_t first = hits.firstSample(p);
                        for (std::size_t i = first; i < first + std::size_t(hits.sampleCount(p)); ++i)
                          if (hits.valid[i] && samplesLobe(hits.hits[i]))
                            addLobeBounce(pooled[p], textureOcclusion(surfaceOf(hits.hits[i])),
                                          settings_.evaluation.lobe_visibility, shading[i]);
                        float weight = 0.0f;
                        setRgb(hdr, int(p % std::size_t(w)), int(p / std::size_t(w)),
                               composePixel(hits, shading, nullptr, p, weight));
                      }
                    });
  return reshaded.load();
}

StaticCounts StaticShading::shade(const HitPointBuffer& hits, const CameraModel& view,
                                  std::vector<SplitSumShading>& shading, std::vector<WalkRay>& walk_rays,
                                  ViewBounces& bounces, cv::Mat& hdr, cv::Mat& coverage,
                                  const AxisAlignedFilter* filter, FilterCounts* filter_counts,
                                  std::vector<FilterChange>* filter_changes) const {
  const int w = hits.width;
  hits.reservePerSample(shading);
  hits.reservePerSample(walk_rays);
  shading.resize(hits.hits.size());
  walk_rays.resize(hits.hits.size());
  const bool pool_bounces = lobe_materials_ && settings_.relic_interreflection &&
                            settings_.evaluation.rough_interreflection_interleaved;
  if (pool_bounces) {
    // A view's pixels hold ~90 bytes each and a few of them are rough: the last pass's rough
    // pixels are reset, not the whole view.
    if (bounces.pixels.size() != hits.pixelCount())
      bounces.pixels.assign(hits.pixelCount(), PixelBounce{});
    else
      for (const std::uint32_t p : bounces.rough) bounces.pixels[p] = PixelBounce{};
    bounces.rough.clear();
  }
  std::vector<PixelBounce>& pixel_bounces = bounces.pixels;
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> marked_rough;
  const float spread = 1.0f / view.intrinsics().fx;  // radians per pixel: the footprint's growth
  tbb::enumerable_thread_specific<StaticCounts> counts;
  tbb::enumerable_thread_specific<DeferredRays> deferred_rays;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hits.covered.size(), 256), [&](const tbb::
                                                                                          blocked_range<
                                                                                              std::size_t>&
                                                                                              r) {
    StaticCounts& local = counts.local();
    DeferredRays& deferred = deferred_rays.local();
    deferred.clear();
    for (std::size_t k = r.begin(); k < r.end(); ++k) {
      const std::size_t p = hits.covered[k];
      const std::size_t first = hits.firstSample(p);
      LobeShare share = pixelLobeShare(hits, p, spread);
      for (share.sample = 0; share.sample < share.samples; ++share.sample) {
        const std::size_t i = first + std::size_t(share.sample);
        if (!hits.valid[i]) continue;
        ++local.shaded_samples;
        if (visibility_ && visibility_->covers(hits.hits[i].location)) ++local.occluded_samples;
        share.cone_width = glm::length(hits.hits[i].position - view.position()) * spread;
        if (settings_.evaluation.lobe_strata_jittered)
          share.stratum_offset = stratumOffset(0, p, share.sample);
        shadeHit(hits.hits[i], p, i, share, shading[i], walk_rays[i], deferred);
      }
    }
    local.interreflection_rays += finishDeferred(
        hits, deferred, shading, walk_rays, [&](std::size_t p, std::size_t i, const LobeBounce& bounce) {
          PixelBounce& pixel = pixel_bounces[p];
          if (!pixel.rough) {
            pixel = {true, hits.hits[i].position, hits.hits[i].normal, hits.hits[i].material.roughness, {}};
            marked_rough.local().push_back(std::uint32_t(p));
          }
          pixel.samples.add(bounce, 1.0f);
        });
    local.interreflected_samples += deferred.samples_casting;
  });
  for (const std::vector<std::uint32_t>& marked : marked_rough)
    bounces.rough.insert(bounces.rough.end(), marked.begin(), marked.end());
  // Each sample's share of its pixel's pooled lobe (the pixel's and its neighbours' samples).
  const auto addLobe = [&](std::size_t p, const LobeBounce& bounce) {
    const std::size_t first = hits.firstSample(p), last = first + std::size_t(hits.sampleCount(p));
    for (std::size_t i = first; i < last; ++i)
      if (hits.valid[i] && samplesLobe(hits.hits[i]))
        addLobeBounce(bounce, textureOcclusion(surfaceOf(hits.hits[i])), settings_.evaluation.lobe_visibility,
                      shading[i]);
  };
  const auto pooledAt = [&](std::size_t p) {
    return poolLobeBounces(pixel_bounces, w, hits.height, view, int(p % std::size_t(w)),
                           int(p / std::size_t(w)));
  };
  // Unfiltered, a pixel's pooled lobe is added where it is made; the filter reads the pooled lobes
  // of a pixel's neighbours, so it gets them all in a view-sized image first.
  std::vector<LobeBounce> pooled, unfiltered;
  if (pool_bounces && !filter) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bounces.rough.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k < r.end(); ++k)
                          addLobe(bounces.rough[k], pooledAt(bounces.rough[k]));
                      });
  } else if (pool_bounces) {
    pooled.resize(hits.pixelCount());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bounces.rough.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k < r.end(); ++k)
                          pooled[bounces.rough[k]] = pooledAt(bounces.rough[k]);
                      });
    if (filter_changes) {
      unfiltered = pooled;
      filter_changes->resize(hits.pixelCount());
    }
    *filter_counts = filter->apply(pixel_bounces, pooled, w, hits.height, view);
  }
  const bool measure = !unfiltered.empty();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hits.covered.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<SplitSumShading> saved;
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t p = hits.covered[k];
                        const int x = int(p % std::size_t(w)), y = int(p / std::size_t(w));
                        float weight = 0.0f;
                        // Filtered: the pooled lobe is added here (unfiltered it already was).
                        const bool rough = !pooled.empty() && pixel_bounces[p].rough;
                        if (rough && measure) {
                          // The pixel without the filter, then its shading as it was.
                          const std::size_t first = hits.firstSample(p);
                          const std::size_t last = first + std::size_t(hits.sampleCount(p));
                          saved.assign(shading.begin() + std::ptrdiff_t(first),
                                       shading.begin() + std::ptrdiff_t(last));
                          addLobe(p, unfiltered[p]);
                          (*filter_changes)[p].unfiltered = composePixel(hits, shading, nullptr, p, weight);
                          std::copy(saved.begin(), saved.end(), shading.begin() + std::ptrdiff_t(first));
                        }
                        if (rough) addLobe(p, pooled[p]);
                        const vec3 rgb = composePixel(hits, shading, nullptr, p, weight);
                        if (rough && measure) (*filter_changes)[p].filtered = rgb;
                        setRgb(hdr, x, y, rgb);
                        coverage.at<float>(y, x) = hits.coverage(x, y);
                      }
                    });
  StaticCounts total;
  for (const StaticCounts& local : counts) total.add(local);
  for (const std::uint64_t rays : sun_rays_) total.sun_rays += rays;
  for (std::uint64_t& rays : wide_lobe_rays_) {
    total.interreflection_rays += rays;
    rays = 0;
  }
  return total;
}

}  // namespace holo::reflect
