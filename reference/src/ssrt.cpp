#include "holo/reference/ssrt.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reference/sampler.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/composition.hpp"
#include "holo/reflect/hit_points.hpp"

namespace holo::reference {

using reflect::AntiAliasing;
using reflect::composeReflection;
using reflect::Frame;
using reflect::HitPoint;
using reflect::HitPointBuffer;
using reflect::PrefilteredIbl;
using reflect::RenderScene;
using reflect::roughnessToAlpha;
using reflect::SplitSumShading;
using reflect::SurfaceMaterial;
using reflect::traceHitPoints;
namespace ggx = reflect::ggx;

void SsrtSettings::validate() const {
  const std::string src = "ssrt settings";
  if (!isFinite(origin)) throw InputError(src, "origin", "a finite point (metres)");
  if (map_width < 8 || map_width > 16384 || map_width % 2 != 0)
    throw InputError(src, "map_width", "an even width in [8, 16384] pixels", std::to_string(map_width));
  if (rays < 1) throw InputError(src, "rays", ">= 1", std::to_string(rays));
  if (steps < 1) throw InputError(src, "steps", ">= 1", std::to_string(steps));
  if (refine_steps < 0) throw InputError(src, "refine_steps", ">= 0", std::to_string(refine_steps));
  if (aa_samples != 1 && aa_samples != 4)
    throw InputError(src, "aa_samples", "1 or 4", std::to_string(aa_samples));
  if (!std::isfinite(max_distance) || !(max_distance > 0.0f))
    throw InputError(src, "max_distance", "a finite distance > 0 (metres)", std::to_string(max_distance));
  if (!std::isfinite(thickness) || !(thickness > 0.0f))
    throw InputError(src, "thickness", "a finite thickness > 0 (metres)", std::to_string(thickness));
  if (!std::isfinite(ray_offset) || ray_offset < 0.0f || ray_offset > 0.1f)
    throw InputError(src, "ray_offset", "0..0.1 metres", std::to_string(ray_offset));
}

ReprojectedRgbd::ReprojectedRgbd(const depthfilter::ForegroundCloud& cloud, const vec3& origin, int width)
    : origin_(origin), width_(width), height_(width / 2) {
  depth_.assign(std::size_t(width_) * std::size_t(height_), 0.0f);
  radiance_.assign(depth_.size(), vec3(0.0f));
  for (const depthfilter::ForegroundPoint& p : cloud.points) {
    const vec3 d = p.position - origin_;
    const float dist = glm::length(d);
    if (!(dist > 1e-6f) || !std::isfinite(dist) || !isFinite(p.radiance)) continue;
    const vec2 uv = equirect::directionToUv(d / dist);
    const int x = std::clamp(int(uv.x * float(width_)), 0, width_ - 1);
    const int y = std::clamp(int(uv.y * float(height_)), 0, height_ - 1);
    const std::size_t i = std::size_t(y) * std::size_t(width_) + std::size_t(x);
    if (depth_[i] == 0.0f) ++filled_;
    // Only the nearest point survives the reprojection: the paper's holes and hidden surfaces.
    if (depth_[i] == 0.0f || dist < depth_[i]) {
      depth_[i] = dist;
      radiance_[i] = glm::max(p.radiance, vec3(0.0f));
    }
  }
}

float ReprojectedRgbd::depthAlong(const vec3& direction, int* pixel) const {
  const vec2 uv = equirect::directionToUv(direction);
  const int x = std::clamp(int(uv.x * float(width_)), 0, width_ - 1);
  const int y = std::clamp(int(uv.y * float(height_)), 0, height_ - 1);
  *pixel = y * width_ + x;
  return depth_[std::size_t(*pixel)];
}

namespace {

struct Marched {
  bool hit = false;
  vec3 radiance{0.0f};
};

// Is the ray point at parameter t behind the map's surface, within the thickness? pixel: where.
bool behindSurface(const ReprojectedRgbd& map, const vec3& origin, const Ray& ray, float t, float thickness,
                   int* pixel) {
  const vec3 q = ray.origin + ray.direction * t - origin;
  const float dist = glm::length(q);
  if (!(dist > 1e-6f)) return false;
  const float d = map.depthAlong(q / dist, pixel);
  return d > 0.0f && dist >= d && dist <= d + thickness;
}

Marched march(const ReprojectedRgbd& map, const SsrtSettings& s, const Ray& ray, float jitter) {
  const float dt = s.max_distance / float(s.steps);
  int pixel = 0;
  for (int i = 0; i < s.steps; ++i) {
    const float t = (float(i) + jitter) * dt;
    if (!behindSurface(map, s.origin, ray, t, s.thickness, &pixel)) continue;
    // Bisect between the last step in front and this one for the surface's own pixel.
    float lo = std::max(0.0f, t - dt), hi = t;
    for (int k = 0; k < s.refine_steps; ++k) {
      const float mid = 0.5f * (lo + hi);
      int p = 0;
      if (behindSurface(map, s.origin, ray, mid, s.thickness, &p)) {
        hi = mid;
        pixel = p;
      } else {
        lo = mid;
      }
    }
    return {true, map.radiance(pixel)};
  }
  return {};
}

}  // namespace

cv::Mat renderSsrt(const RenderScene& scene, const PrefilteredIbl& ibl,
                   const depthfilter::ForegroundCloud& cloud, const CameraModel& view,
                   const SsrtSettings& settings, SsrtStats* stats) {
  settings.validate();
  const ReprojectedRgbd map(cloud, settings.origin, settings.map_width);
  HitPointBuffer hits;
  traceHitPoints(scene, view, settings.aa_samples == 4 ? AntiAliasing::Full : AntiAliasing::None, hits);
  const int w = view.width(), h = view.height();
  cv::Mat out(h, w, CV_32FC3, cv::Scalar::all(0));
  std::atomic<std::uint64_t> all_rays{0}, all_hits{0};
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    std::uint64_t local_rays = 0, local_hits = 0;
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < w; ++x) {
        vec3 sum(0.0f);
        const std::size_t pixel = std::size_t(y) * std::size_t(w) + std::size_t(x);
        const int samples = hits.sampleCount(pixel);
        for (int s = 0; s < samples; ++s) {
          const std::size_t i = hits.firstSample(pixel) + std::size_t(s);
          if (!hits.valid[i]) continue;
          const HitPoint& hp = hits.hits[i];
          const float nv = glm::dot(hp.normal, hp.to_viewer);
          if (!(nv > 0.0f)) continue;
          // The split-sum shading of the static IBL, as ours.
          const SurfaceMaterial& m = hp.material;
          const SplitSumShading shading =
              ibl.shadeParts(m, hp.normal, hp.to_viewer, hp.reflected, hp.position);
          const vec3& scale = shading.specular_scale;
          const vec3& diffuse = shading.diffuse;
          const vec3 psi_s = scale * shading.environment;

          const bool mirror = m.roughness < 0.01f;
          const float alpha = roughnessToAlpha(m.roughness);
          const Frame frame(hp.normal);
          const vec3 wo_local = frame.toLocal(hp.to_viewer);
          SampleStream stream(settings.seed, std::uint32_t(y * w + x), std::uint32_t(s));
          vec3 found(0.0f);
          int n_hit = 0;
          for (int r = 0; r < settings.rays; ++r) {
            const vec2 u = stream.next2D();
            const float jitter = stream.next1D();
            vec3 dir = hp.reflected;
            if (!mirror) {
              const vec3 hn = frame.toWorld(ggx::sampleVisibleNormal(wo_local, alpha, u));
              dir = glm::reflect(-hp.to_viewer, hn);
              if (!(glm::dot(dir, hp.normal) > 0.0f)) continue;  // below the surface: no foreground
            }
            ++local_rays;
            const Ray ray{hp.position + hp.normal * settings.ray_offset, glm::normalize(dir)};
            const Marched mr = march(map, settings, ray, jitter);
            if (!mr.hit) continue;
            found += mr.radiance;
            ++n_hit;
          }
          local_hits += std::uint64_t(n_hit);
          const float weight = float(n_hit) / float(settings.rays);
          const vec3 psi_d = n_hit > 0 ? scale * found / float(n_hit) : vec3(0.0f);
          sum += composeReflection(psi_d, psi_s, weight) + composeReflection(diffuse, vec3(0.0f), 1.0f);
        }
        setRgb(out, x, y, sum / float(samples));
      }
    all_rays += local_rays;
    all_hits += local_hits;
  });
  if (stats) {
    stats->rays = all_rays;
    stats->hits = all_hits;
    stats->filled_pixels = map.filledPixels();
  }
  return out;
}

}  // namespace holo::reference
