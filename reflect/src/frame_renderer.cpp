#include "holo/reflect/frame_renderer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/composition.hpp"
#include "holo/reflect/tone_map.hpp"

namespace holo::reflect {
namespace {

class PassTimer {
 public:
  PassTimer(std::vector<PassTiming>& out, Pass pass)
      : out_(out), pass_(pass), start_(std::chrono::steady_clock::now()) {}
  ~PassTimer() {
    const auto end = std::chrono::steady_clock::now();
    out_.push_back({pass_, std::chrono::duration<double, std::milli>(end - start_).count()});
  }
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

 private:
  std::vector<PassTiming>& out_;
  Pass pass_;
  std::chrono::steady_clock::time_point start_;
};

// Where a ray that misses every voxel first passes within `radius_per_m * t` metres of an occupied
// brick, for t in (0, t_max]; none when it never does. Marches the brick level by steps of half a
// brick, jumping where the brick distance proves the space around empty: a brick at Chebyshev
// distance k (in bricks) from the nearest occupied one is at least (k - 1) bricks from any
// occupied voxel.
std::optional<float> nearMissT(const depthfilter::VoxelGrid& grid, const Ray& ray, float t_max,
                               float radius_per_m) {
  const float brick_m = grid.voxelSize() * float(grid.brickSize());
  const Bounds3 box{grid.origin(), grid.origin() + vec3(grid.dims()) * grid.voxelSize()};
  float t0 = 0.0f, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    if (ray.direction[a] == 0.0f) {
      if (!(ray.origin[a] >= box.lo[a] && ray.origin[a] < box.hi[a])) return std::nullopt;
      continue;
    }
    const float inv = 1.0f / ray.direction[a];
    float ta = (box.lo[a] - ray.origin[a]) * inv, tb = (box.hi[a] - ray.origin[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  const glm::ivec3 bricks = grid.brickDims();
  // The ray in brick units, so that a step's brick is one floor.
  const vec3 origin_b = (ray.origin - box.lo) / brick_m, direction_b = ray.direction / brick_m;
  // Every iteration advances t by at least half a brick: the loop is bounded by the box.
  for (float t = std::max(t0, 0.5f * brick_m); t <= t1;) {
    const vec3 at = glm::floor(origin_b + direction_b * t);
    if (glm::any(glm::lessThan(at, vec3(0.0f))) || glm::any(glm::greaterThanEqual(at, vec3(bricks)))) break;
    const glm::ivec3 b(at);
    const float gap = float(std::max(int(grid.brickDistance(b)) - 1, 0)) * brick_m;
    const float radius = radius_per_m * t;
    if (grid.brickCount(b) > 0 || gap <= radius) return t;
    t += std::max(0.5f * brick_m, gap - radius_per_m * (t + gap));
  }
  return std::nullopt;
}

}  // namespace

void TracerSettings::validate() const {
  const std::string src = "tracer settings";
  if (pyramid_levels < 1 || pyramid_levels > kMaxPyramidLevels)
    throw InputError(src, "pyramid_levels", "1.." + std::to_string(kMaxPyramidLevels),
                     std::to_string(pyramid_levels));
  if (aa_samples != 1 && aa_samples != 4)
    throw InputError(src, "aa_samples", "1 or 4", std::to_string(aa_samples));
  if (!std::isfinite(max_reflection_distance) || !(max_reflection_distance > 0.0f))
    throw InputError(src, "max_reflection_distance", "a finite distance > 0 (metres)",
                     std::to_string(max_reflection_distance));
  if (!std::isfinite(ray_offset) || ray_offset < 0.0f || ray_offset > 0.1f)
    throw InputError(src, "ray_offset", "0..0.1 metres", std::to_string(ray_offset));
  if (!std::isfinite(exposure)) throw InputError(src, "exposure", "a finite number (<= 0 for automatic)");
  if (!std::isfinite(static_reuse_distance) || static_reuse_distance < 0.0f)
    throw InputError(src, "static_reuse_distance", "a finite distance >= 0 (metres)",
                     std::to_string(static_reuse_distance));
  if (!std::isfinite(level_bias) || std::abs(level_bias) > float(kMaxPyramidLevels))
    throw InputError(src, "level_bias", "a finite level offset within +-" + std::to_string(kMaxPyramidLevels),
                     std::to_string(level_bias));
  if (!std::isfinite(lobe_fallback_roughness) || lobe_fallback_roughness < 0.0f)
    throw InputError(src, "lobe_fallback_roughness", "a roughness >= 0 (> 1: never)",
                     std::to_string(lobe_fallback_roughness));
  if (!std::isfinite(walk_per_pixel_roughness) || walk_per_pixel_roughness < 0.0f)
    throw InputError(src, "walk_per_pixel_roughness", "a roughness >= 0 (> 1: never)",
                     std::to_string(walk_per_pixel_roughness));
  if (edge_aa && aa_samples != 1) throw InputError(src, "edge_aa", "only with aa_samples 1", "aa_samples 4");
  if (!std::isfinite(foreground_map_roughness) || foreground_map_roughness < 0.0f)
    throw InputError(src, "foreground_map_roughness", "a roughness >= 0 (> 1: never)",
                     std::to_string(foreground_map_roughness));
  if (foreground_map_width < 8 || foreground_map_width > 1024 || foreground_map_width % 2 != 0)
    throw InputError(src, "foreground_map_width", "an even number of texels in 8..1024",
                     std::to_string(foreground_map_width));
  if (rough_interreflection_grid != 1 && (rough_interreflection_grid < 2 || rough_interreflection_grid > 8 ||
                                          rough_interreflection_grid % 2 != 0))
    throw InputError(src, "rough_interreflection_grid", "1 (the mirror ray) or an even side 2..8",
                     std::to_string(rough_interreflection_grid));
  if (lobe_components < 1 || lobe_components > kMaxLobeComponents)
    throw InputError(src, "lobe_components", "1.." + std::to_string(kMaxLobeComponents),
                     std::to_string(lobe_components));
  grid.validate(src + " grid");
}

FrameRenderer::FrameRenderer(const RenderScene& scene, const PrefilteredIbl& ibl, TracerSettings settings)
    : scene_(scene), ibl_(ibl), settings_((settings.validate(), settings)), grid_(settings_.grid) {
  for (const Material& m : scene_.relic().materials)
    if (m.roughness < kGlossyRoughnessLimit || m.metallic_roughness_texture.used()) relic_glossy_ = true;
  if (scene_.relic().materials.empty()) relic_glossy_ = true;  // default material: be safe
  relic_bounds_ = scene_.relicBounds();
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
}

EffectPlan FrameRenderer::plan(const depthfilter::ForegroundCloud& cloud,
                               const std::vector<ForegroundCameraImage>& cameras) const {
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
  return planEffects(in);
}

struct FrameRenderer::WalkRay {
  vec3 position{0.0f}, normal{0.0f, 1.0f, 0.0f}, reflected{0.0f, 1.0f, 0.0f};
  float roughness = 0.0f;
  bool bounced = false;  // from the interreflection's second point
};

struct FrameRenderer::LobeBounce {
  float above = 0.0f, met = 0.0f;      // lobe samples above the surface; those that met the relic
  vec3 diffuse{0.0f}, specular{0.0f};  // sums over the met ones of their second points' shading
  void add(const LobeBounce& other, float weight) {
    above += weight * other.above;
    met += weight * other.met;
    diffuse += weight * other.diffuse;
    specular += weight * other.specular;
  }
};

// A pixel's interleaved lobe samples and where they lie (its first rough sample's point).
struct FrameRenderer::PixelBounce {
  bool rough = false;
  vec3 position{0.0f}, normal{0.0f};
  LobeBounce samples;
};

bool FrameRenderer::readsRoughMap(float roughness) const {
  return rough_map_ && roughness >= settings_.foreground_map_roughness;
}

std::optional<FrameRenderer::LobeBounce> FrameRenderer::shadeHit(const HitPoint& hp, const LobeShare& share,
                                                                 SplitSumShading& shading,
                                                                 WalkRay& walk_ray) const {
  shading = ibl_.shadeParts(hp.material, hp.normal, hp.to_viewer, hp.reflected);
  walk_ray = {hp.position, hp.normal, hp.reflected, hp.material.roughness, false};
  if (!settings_.relic_interreflection) return std::nullopt;
  if (settings_.rough_interreflection_grid > 1 && readsRoughMap(hp.material.roughness)) {
    const LobeBounce bounce = traceLobeBounce(hp, share);
    if (settings_.rough_interreflection_interleaved) return bounce;
    addLobeBounce(bounce, shading);
    return std::nullopt;
  }
  const RayScene& relic = scene_.relicOnly();
  const Ray ray{hp.position + hp.normal * settings_.ray_offset, hp.reflected};
  const RayHit hit = relic.intersect(ray);
  if (!hit.hit()) return std::nullopt;
  const vec3 position = relic.position(ray, hit);
  const vec3 normal = relic.shadingNormal(hit, ray.direction);
  const vec3 reflected = glm::reflect(ray.direction, normal);
  if (!isFinite(position) || !isFinite(normal) || !isFinite(reflected)) return std::nullopt;
  const SurfaceMaterial material = scene_.relicMaterial(hit, relic);
  const SplitSumShading second = ibl_.shadeParts(material, normal, -ray.direction, reflected);
  // L = diffuse_1 + s_1 L_2 and L_2 = diffuse_2 + s_2 (psi_d w + env_2 (1 - w)): the composition's
  // form with scale s_1 s_2 and environment env_2.
  shading.diffuse += shading.specular_scale * second.diffuse;
  shading.specular_scale *= second.specular_scale;
  shading.environment = second.environment;
  // The two lobes widen each other: GGX alphas (roughness^2) add in quadrature.
  const float a1 = hp.material.roughness * hp.material.roughness,
              a2 = material.roughness * material.roughness;
  walk_ray = {position, normal, reflected, std::sqrt(std::sqrt(a1 * a1 + a2 * a2)), true};
  return std::nullopt;
}

namespace {

// The stratum centres (the u of ggx::sampleVisibleNormal) of a side x side grid over the lobe
// that one hit point traces. Interleaved: the 2x2 pixel classes take every other stratum in each
// direction (each class alone a coarse grid over the whole lobe), dealt round-robin to the
// pixel's samples; a 3x3 tent over the pixels then sums every stratum with equal weight.
template <class F>
void forEachLobeStratum(int side, bool interleaved, int pixel_class, int sample, int samples, F&& f) {
  const auto centre = [&](int i, int j) {
    f(vec2((float(i) + 0.5f) / float(side), (float(j) + 0.5f) / float(side)));
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

}  // namespace

FrameRenderer::LobeBounce FrameRenderer::traceLobeBounce(const HitPoint& hp, const LobeShare& share) const {
  LobeBounce bounce;
  const Frame frame(hp.normal);
  const vec3 wo = frame.toLocal(hp.to_viewer);
  if (!(wo.z > 0.0f)) return bounce;
  const float alpha = std::max(hp.material.roughness * hp.material.roughness, 1e-3f);
  const RayScene& relic = scene_.relicOnly();
  forEachLobeStratum(settings_.rough_interreflection_grid, settings_.rough_interreflection_interleaved,
                     share.pixel_class, share.sample, share.samples, [&](const vec2& u) {
                       const vec3 l =
                           glm::reflect(-hp.to_viewer, frame.toWorld(ggx::sampleVisibleNormal(wo, alpha, u)));
                       if (!(glm::dot(l, hp.normal) > 0.0f)) return;
                       bounce.above += 1.0f;
                       const Ray ray{hp.position + hp.normal * settings_.ray_offset, l};
                       const RayHit hit = relic.intersect(ray);
                       if (!hit.hit()) return;
                       const vec3 normal = relic.shadingNormal(hit, ray.direction);
                       const vec3 reflected = glm::reflect(ray.direction, normal);
                       if (!isFinite(normal) || !isFinite(reflected)) return;
                       const SplitSumShading second = ibl_.shadeParts(scene_.relicMaterial(hit, relic),
                                                                      normal, -ray.direction, reflected);
                       bounce.diffuse += second.diffuse;
                       bounce.specular += second.specular_scale * second.environment;
                       bounce.met += 1.0f;
                     });
  return bounce;
}

void FrameRenderer::addLobeBounce(const LobeBounce& bounce, SplitSumShading& shading) {
  if (!(bounce.met > 0.0f)) return;
  // The share of the lobe that meets the relic sees its second points' static shading (their own
  // foreground is left out: the rough map read at the first point stands for the whole lobe).
  const float fraction = std::min(bounce.met / bounce.above, 1.0f);
  shading.diffuse += shading.specular_scale * fraction * bounce.diffuse / bounce.met;
  shading.environment = (1.0f - fraction) * shading.environment + fraction * bounce.specular / bounce.met;
}

struct FrameRenderer::ViewCache {
  CameraModel camera;
  bool ready = false;
  HitPointBuffer hits;
  std::vector<SplitSumShading> shading;    // per entry of hits.hits
  std::vector<WalkRay> walk_rays;          // per entry of hits.hits
  std::vector<PixelBounce> bounces;        // per pixel, its interleaved rough lobe samples (scratch)
  std::vector<ForegroundSample> fg;        // per entry of hits.hits, this frame's walk (scratch)
  std::vector<ForegroundSample> pixel_fg;  // per pixel, the walk of its centre or mean ray (scratch)
  // Per pixel: 0 no relic, 1 walk missed, 2 met, 3 no pixel walk (its sub-samples' rays reflect
  // partly off the relic itself) (scratch).
  std::vector<std::uint8_t> pixel_state;
  // The static result. Never written once handed out: a rebuild allocates new images, so a
  // caller's FrameResult keeps the pixels it was given.
  cv::Mat hdr, coverage, display, zero_weight;
  float display_exposure = 0.0f;  // the exposure `display` was tone-mapped at; 0: none
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
  result.plan = plan(cloud, cameras);
  if (result.plan.has(Pass::VoxelGrid)) {
    PassTimer t(result.frame_timings, Pass::VoxelGrid);
    grid_.build(cloud);
  } else {
    grid_.clear();
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
  while (caches_.size() < views.size()) caches_.push_back(std::make_unique<ViewCache>());
  for (std::size_t v = 0; v < views.size(); ++v)
    result.views.push_back(renderView(result.plan, cameras, views[v], *caches_[v]));
  return result;
}

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

// psi_f of one pixel: the mean over its samples of the composed specular plus the diffuse,
// misses black; also the mean foreground weight. `fg` null: no foreground (w = 0).
vec3 composePixel(const HitPointBuffer& hits, const std::vector<SplitSumShading>& shading,
                  const std::vector<ForegroundSample>* fg, std::size_t p, float& weight) {
  const std::size_t first = hits.firstSample(p);
  const int count = hits.sampleCount(p);
  vec3 sum(0.0f);
  float wsum = 0.0f;
  for (std::size_t i = first; i < first + std::size_t(count); ++i) {
    if (!hits.valid[i]) continue;
    const SplitSumShading& sh = shading[i];
    const vec3 psi_s = sh.specular_scale * sh.environment;
    const float w = fg ? (*fg)[i].weight : 0.0f;
    const vec3 psi_d = fg ? sh.specular_scale * (*fg)[i].radiance : vec3(0.0f);
    sum += composeReflection(psi_d, psi_s, w) + composeReflection(sh.diffuse, vec3(0.0f), 1.0f);
    wsum += w;
  }
  const float inv = 1.0f / float(count);
  weight = std::clamp(wsum * inv, 0.0f, 1.0f);
  return sum * inv;
}

}  // namespace

void FrameRenderer::poolLobeBounces(const HitPointBuffer& hits, const std::vector<PixelBounce>& bounces,
                                    const CameraModel& view, int x, int y,
                                    std::vector<SplitSumShading>& shading) const {
  const std::size_t p = std::size_t(y) * std::size_t(hits.width) + std::size_t(x);
  const PixelBounce& own = bounces[p];
  if (!own.rough) return;
  // Neighbours on the same surface only: a few pixels' footprint away and facing alike.
  const float reach = 4.0f * glm::length(own.position - view.position()) / view.intrinsics().fx;
  LobeBounce sum;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if (nx < 0 || ny < 0 || nx >= hits.width || ny >= hits.height) continue;
      const PixelBounce& other = bounces[std::size_t(ny) * std::size_t(hits.width) + std::size_t(nx)];
      if (!other.rough || glm::dot(other.normal, own.normal) < 0.9f ||
          glm::length(other.position - own.position) > reach)
        continue;
      sum.add(other.samples, float((2 - std::abs(dx)) * (2 - std::abs(dy))));
    }
  const std::size_t first = hits.firstSample(p);
  for (std::size_t i = first; i < first + std::size_t(hits.sampleCount(p)); ++i)
    if (hits.valid[i] && readsRoughMap(hits.hits[i].material.roughness)) addLobeBounce(sum, shading[i]);
}

ViewImages FrameRenderer::renderView(const EffectPlan& plan,
                                     const std::vector<ForegroundCameraImage>& cameras,
                                     const CameraModel& view, ViewCache& cache) const {
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

  out.static_reused = cache.ready && reusable(cache.camera, view, settings_.static_reuse_distance);
  if (!out.static_reused) {
    {
      PassTimer t(out.timings, Pass::HitPoints);
      const AntiAliasing aa = settings_.aa_samples == 4 ? AntiAliasing::Full
                              : settings_.edge_aa       ? AntiAliasing::Edges
                                                        : AntiAliasing::None;
      traceHitPoints(scene_, view, aa, cache.hits, relic_bounds_);
    }
    PassTimer t(out.timings, Pass::StaticReflections);
    const HitPointBuffer& hits = cache.hits;
    cache.shading.resize(hits.hits.size());
    cache.walk_rays.resize(hits.hits.size());
    const bool pool_bounces = rough_map_ && settings_.relic_interreflection &&
                              settings_.rough_interreflection_grid > 1 &&
                              settings_.rough_interreflection_interleaved;
    if (pool_bounces) cache.bounces.assign(hits.pixelCount(), PixelBounce{});
    // New images (see ViewCache): the previous ones may still be held by a caller. Only the
    // covered pixels have anything to shade; the rest stay black.
    cache.hdr = cv::Mat(h, w, CV_32FC3, cv::Scalar::all(0));
    cache.coverage = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
    cache.zero_weight = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hits.covered.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k < r.end(); ++k) {
                          const std::size_t p = hits.covered[k];
                          const std::size_t first = hits.firstSample(p);
                          const int x = int(p % std::size_t(w)), y = int(p / std::size_t(w));
                          LobeShare share{(x & 1) + 2 * (y & 1), 0, hits.sampleCount(p)};
                          for (share.sample = 0; share.sample < share.samples; ++share.sample) {
                            const std::size_t i = first + std::size_t(share.sample);
                            if (!hits.valid[i]) continue;
                            const std::optional<LobeBounce> bounce =
                                shadeHit(hits.hits[i], share, cache.shading[i], cache.walk_rays[i]);
                            if (!bounce) continue;
                            PixelBounce& pixel = cache.bounces[p];
                            if (!pixel.rough) pixel = {true, hits.hits[i].position, hits.hits[i].normal, {}};
                            pixel.samples.add(*bounce, 1.0f);
                          }
                        }
                      });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hits.covered.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k < r.end(); ++k) {
                          const std::size_t p = hits.covered[k];
                          const int x = int(p % std::size_t(w)), y = int(p / std::size_t(w));
                          if (pool_bounces) poolLobeBounces(hits, cache.bounces, view, x, y, cache.shading);
                          float weight = 0.0f;
                          setRgb(cache.hdr, x, y, composePixel(hits, cache.shading, nullptr, p, weight));
                          cache.coverage.at<float>(y, x) = hits.coverage(x, y);
                        }
                      });
    cache.camera = view;
    cache.display_exposure = 0.0f;
    cache.ready = true;
  }
  if (fixed_exposure && cache.display_exposure != settings_.exposure) {
    PassTimer t(out.timings, Pass::ToneMap);
    // Black where the relic is not (toneMapPixel(0) is black), tone-mapped where it is.
    cache.display = cv::Mat(h, w, CV_8UC3, cv::Scalar::all(0));
    const std::vector<std::uint32_t>& covered = cache.hits.covered;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, covered.size(), 256),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t k = r.begin(); k < r.end(); ++k) {
            const int x = int(covered[k] % std::size_t(w)), y = int(covered[k] / std::size_t(w));
            cache.display.at<cv::Vec3b>(y, x) = toneMapPixel(rgbAt(cache.hdr, x, y), settings_.exposure);
          }
        });
    cache.display_exposure = settings_.exposure;
  }
  const HitPointBuffer& hits = cache.hits;
  out.camera = cache.camera;
  out.refined_pixels = hits.refined.size();
  out.coverage = cache.coverage;

  if (!plan.has(Pass::ForegroundWalk)) {
    out.hdr = cache.hdr;
    out.weight = cache.zero_weight;
  } else {
    // Scratch sized once; only the covered pixels' entries are written and read below.
    cache.fg.resize(hits.hits.size());
    {
      PassTimer t(out.timings, Pass::ForegroundWalk);
      std::atomic<std::uint64_t> walked{0}, found{0};
      const std::vector<LobeComponent> lobe = ggxLobeMixture(settings_.lobe_components);
      // The pyramid's blurred foreground at `pixel` for a lobe of `roughness` that travelled
      // travel_m to a point camera_m from the camera: one read per Gaussian of the lobe, the
      // premultiplied colours and the weights mixed.
      const auto readLobe = [&](const ForegroundPyramid& pyramid, const vec2& pixel, float roughness,
                                float travel_m, float camera_m, float focal_px) {
        const float sigma = reflectedLobeSigma(roughness);
        ForegroundSample mixed;
        vec3 premultiplied(0.0f);
        for (const LobeComponent& c : lobe) {
          const float level = std::clamp(foregroundLevelForLobe(sigma * c.sigma_scale, travel_m, camera_m,
                                                                focal_px, settings_.pyramid_levels) +
                                             settings_.level_bias,
                                         0.0f, float(settings_.pyramid_levels - 1));
          const ForegroundSample s = pyramid.sample(pixel, level);
          premultiplied += c.weight * s.weight * s.radiance;
          mixed.weight += c.weight * s.weight;
        }
        if (mixed.weight > 0.0f) mixed.radiance = premultiplied / mixed.weight;
        return mixed;
      };
      // The foreground of one reflected ray: the first occupied voxel, read from the pyramid of
      // the camera that saw it at the level of the lobe's footprint there.
      const auto walk = [&](const vec3& position, const vec3& normal, const vec3& reflected, float roughness,
                            ForegroundSample& sample) {
        if (readsRoughMap(roughness)) {
          sample = rough_map_->lookup(reflected, roughness);
          return sample.weight > 0.0f;
        }
        const Ray ray{position + normal * settings_.ray_offset, reflected};
        const VoxelHit vh = firstOccupiedVoxel(grid_, ray, settings_.max_reflection_distance);
        if (!vh.hit()) {
          if (roughness < settings_.lobe_fallback_roughness) return false;
          const float tan_sigma = std::tan(reflectedLobeSigma(roughness));
          const std::optional<float> t_near =
              nearMissT(grid_, ray, settings_.max_reflection_distance, 2.0f * tan_sigma);
          if (!t_near) return false;
          // The camera looking most along the ray that sees the point.
          const vec3 p = ray.origin + ray.direction * *t_near;
          int best = -1;
          float best_dot = -2.0f;
          vec2 best_px(0.0f);
          for (std::size_t c = 0; c < pyramids_.size(); ++c) {
            if (pyramids_[c].empty()) continue;
            const CameraModel& cam = cameras[c].camera;
            float depth = 0.0f;
            const std::optional<vec2> px = cam.project(p, &depth);
            if (!px || !(depth > 0.0f) || px->x < 0.0f || px->y < 0.0f || px->x > float(cam.width() - 1) ||
                px->y > float(cam.height() - 1))
              continue;
            const float d = glm::dot(ray.direction, glm::normalize(vec3(cam.T_world_camera()[2])));
            if (d > best_dot) best_dot = d, best = int(c), best_px = *px;
          }
          if (best < 0) return false;
          const CameraModel& cam = cameras[std::size_t(best)].camera;
          sample = readLobe(pyramids_[std::size_t(best)], best_px, roughness, *t_near,
                            glm::length(p - cam.position()), cam.intrinsics().fx);
          return sample.weight > 0.0f;
        }
        const depthfilter::VoxelSample& vs = grid_.sample(vh.sample);
        if (vs.camera >= pyramids_.size() || pyramids_[vs.camera].empty()) return false;
        const CameraModel& cam = cameras[vs.camera].camera;
        // The point the ray reaches: half a voxel into the one it entered.
        const vec3 p = ray.origin + ray.direction * (vh.t + 0.5f * grid_.voxelSize());
        float depth = 0.0f;
        const std::optional<vec2> px = cam.project(p, &depth);
        const vec2 pixel = px ? *px : vec2(vs.x, vs.y);
        sample = readLobe(pyramids_[vs.camera], pixel, roughness, vh.t, glm::length(p - cam.position()),
                          cam.intrinsics().fx);
        return true;
      };
      const std::size_t pixels = hits.pixelCount();
      const std::vector<std::uint32_t>& covered = hits.covered;
      // Pixel state of a pixel whose sub-samples reflect partly off the relic itself: no pixel walk.
      constexpr std::uint8_t kMixedBounce = 3;
      // Pass 1: one walk per covered pixel (its centre, or the mean ray of its valid
      // sub-samples). Pixel states: 0 nothing of the relic, 1 its walk missed, 2 it met the
      // foreground, kMixedBounce no walk.
      cache.pixel_fg.resize(pixels);
      cache.pixel_state.assign(pixels, 0);
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, covered.size(), 256),
          [&](const tbb::blocked_range<std::size_t>& r) {
            std::uint64_t local_walked = 0, local_found = 0;
            for (std::size_t k = r.begin(); k < r.end(); ++k) {
              const std::size_t p = covered[k];
              cache.pixel_fg[p] = ForegroundSample{};
              const std::size_t first = hits.firstSample(p);
              for (std::size_t i = first; i < first + std::size_t(hits.sampleCount(p)); ++i)
                cache.fg[i] = ForegroundSample{};
              const std::size_t count = std::size_t(hits.sampleCount(p));
              vec3 position(0.0f), normal(0.0f), reflected(0.0f);
              float roughness = 0.0f;
              int valid = 0, bounced = 0;
              for (std::size_t i = first; i < first + count; ++i) {
                if (!hits.valid[i]) continue;
                const WalkRay& wr = cache.walk_rays[i];
                position += wr.position;
                normal += wr.normal;
                reflected += wr.reflected;
                roughness += wr.roughness;
                bounced += wr.bounced;
                ++valid;
              }
              if (valid == 0) continue;
              const float inv = 1.0f / float(valid);
              const float nl = glm::length(normal), rl = glm::length(reflected);
              cache.pixel_state[p] = 1;
              // Opposite sub-samples, or some reflected directly and some off the relic: no mean
              // ray (the sub-samples walk, pass 2).
              if (bounced != 0 && bounced != valid) cache.pixel_state[p] = kMixedBounce;
              if (!(nl > 1e-6f) || !(rl > 1e-6f) || cache.pixel_state[p] == kMixedBounce) continue;
              ++local_walked;
              if (!walk(position * inv, normal / nl, reflected / rl, roughness * inv, cache.pixel_fg[p]))
                continue;
              ++local_found;
              cache.pixel_state[p] = 2;
            }
            walked += local_walked;
            found += local_found;
          });
      // Pass 2: a pixel with four sub-samples keeps its one walk where its lobe is rough, or where
      // the foreground it met (or missed) matches its 8 neighbours'; at the reflected foreground's
      // edges (a neighbour met it and this one did not, or their weights differ by more than
      // kEdgeWeightStep) each sub-sample walks, which anti-aliases those edges as four walks
      // everywhere would.
      constexpr float kEdgeWeightStep = 0.2f;
      const int w_px = hits.width, h_px = hits.height;
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, covered.size(), 256),
          [&](const tbb::blocked_range<std::size_t>& r) {
            std::uint64_t local_walked = 0, local_found = 0;
            for (std::size_t k = r.begin(); k < r.end(); ++k) {
              const std::size_t p = covered[k];
              if (cache.pixel_state[p] == 0) continue;
              const std::size_t first = hits.firstSample(p);
              const std::size_t count = std::size_t(hits.sampleCount(p));
              const bool mixed = cache.pixel_state[p] == kMixedBounce;
              bool rough = !mixed;
              for (std::size_t i = first; i < first + count && rough; ++i)
                rough = !hits.valid[i] || cache.walk_rays[i].roughness >= settings_.walk_per_pixel_roughness;
              bool edge = false;
              if (count > 1 && !rough && settings_.walk_edges_only) {
                const int x = int(p % std::size_t(w_px)), y = int(p / std::size_t(w_px));
                for (int dy = -1; dy <= 1 && !edge; ++dy)
                  for (int dx = -1; dx <= 1 && !edge; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w_px || ny >= h_px) continue;
                    const std::size_t q = std::size_t(ny) * std::size_t(w_px) + std::size_t(nx);
                    if (cache.pixel_state[q] == 0) continue;  // beyond the relic's silhouette
                    edge = cache.pixel_state[q] != cache.pixel_state[p] ||
                           std::abs(cache.pixel_fg[q].weight - cache.pixel_fg[p].weight) > kEdgeWeightStep;
                  }
              }
              if (mixed || (count > 1 && !rough && (edge || !settings_.walk_edges_only))) {
                for (std::size_t i = first; i < first + count; ++i) {
                  if (!hits.valid[i]) continue;
                  const WalkRay& wr = cache.walk_rays[i];
                  ++local_walked;
                  local_found += walk(wr.position, wr.normal, wr.reflected, wr.roughness, cache.fg[i]);
                }
                continue;
              }
              if (cache.pixel_state[p] != 2) continue;
              for (std::size_t i = first; i < first + count; ++i)
                if (hits.valid[i]) cache.fg[i] = cache.pixel_fg[p];
            }
            walked += local_walked;
            found += local_found;
          });
      out.walked_rays = walked;
      out.foreground_hits = found;
    }
    // Composition over a copy of the static image, only where some foreground was reached (the
    // rest is the static result already), tone-mapping those pixels too when the exposure is
    // fixed.
    PassTimer t(out.timings, Pass::Composition);
    out.hdr = cache.hdr.clone();
    out.weight = cache.zero_weight.clone();
    if (fixed_exposure) out.display = cache.display.clone();
    std::atomic<std::size_t> composed{0};
    const std::vector<std::uint32_t>& covered = hits.covered;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, covered.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        std::size_t local = 0;
                        for (std::size_t k = r.begin(); k < r.end(); ++k) {
                          const std::size_t p = covered[k];
                          const int x = int(p % std::size_t(w)), y = int(p / std::size_t(w));
                          const std::size_t first = hits.firstSample(p);
                          bool reached = false;
                          for (std::size_t i = first; i < first + std::size_t(hits.sampleCount(p)); ++i)
                            reached = reached || cache.fg[i].weight > 0.0f;
                          if (!reached) continue;
                          float weight = 0.0f;
                          const vec3 c = composePixel(hits, cache.shading, &cache.fg, p, weight);
                          setRgb(out.hdr, x, y, c);
                          out.weight.at<float>(y, x) = weight;
                          if (fixed_exposure)
                            out.display.at<cv::Vec3b>(y, x) = toneMapPixel(c, settings_.exposure);
                          ++local;
                        }
                        composed += local;
                      });
    out.composed_pixels = composed;
  }
  if (fixed_exposure) {
    out.exposure = settings_.exposure;
    if (out.display.empty()) out.display = cache.display;
  } else {
    PassTimer t(out.timings, Pass::ToneMap);
    out.exposure = autoExposure(out.hdr);
    out.display = toneMap(out.hdr, out.exposure);
  }
  return out;
}

}  // namespace holo::reflect
