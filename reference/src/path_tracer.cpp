#include "holo/reference/path_tracer.hpp"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <mutex>

#include "holo/core/progress.hpp"
#include "holo/core/stats.hpp"
#include "holo/reference/dielectric.hpp"
#include "holo/reflect/optics.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/view.hpp"
#include "surface_rays.hpp"

namespace holo::reference {

using reflect::attenuationCoefficient;
using reflect::Environment;
using reflect::EnvironmentSample;
using reflect::primaryRay;
using reflect::RenderScene;
using reflect::resolveSurface;
using reflect::SurfaceMaterial;
using reflect::SurfacePoint;
using reflect::transmittance;

PathTracer::PathTracer(const RenderScene& scene, const Environment& environment, PathTracerOptions options)
    : scene_(scene), environment_(environment), options_(options) {
  options_.max_bounces = std::max(1, options_.max_bounces);
  options_.max_dielectric_bounces = std::max(1, options_.max_dielectric_bounces);
  options_.tile_size = std::max(1, options_.tile_size);
}

vec3 PathTracer::traceFromRelic(const Ray& primary, const RayHit& relic_hit, SampleStream& stream,
                                float pixel_spread, PathRecord* record) const {
  vec3 radiance(0.0f);
  vec3 throughput(1.0f);
  Ray ray = primary;
  RayHit hit = relic_hit;
  const RayScene* hit_scene = &scene_.relicOnly();
  const RayScene& all = scene_.all();
  float travelled = 0.0f;  // metres along the path: the pixel's footprint is travelled x spread
  // The medium the path is in: air, or the volume of the relic material it last entered.
  bool in_volume = false;
  vec3 absorption(0.0f);  // 1/m of that volume
  float medium_ior = 1.0f;
  int scatterings = 0, dielectric_scatterings = 0;
  for (;;) {
    travelled += hit.t;
    const SurfacePoint surface = resolveSurface(scene_, *hit_scene, ray, hit, travelled * pixel_spread);
    const vec3 p = surface.position;
    const vec3 n = surface.normal;
    const vec3 ng = hit.geometric_normal;
    if (!isFinite(n) || !isFinite(ng) || !isFinite(p)) break;
    // Added only when non-zero: an overflowed throughput times zero would make the sample NaN.
    if (surface.emission != vec3(0.0f)) radiance += throughput * surface.emission;
    if (scatterings == options_.max_bounces || dielectric_scatterings == options_.max_dielectric_bounces) {
      if (record) {
        record->truncated = true;
        // Radiance inside a medium of IOR n is n^2 times what it carries back into air.
        record->truncated_throughput = luminance(throughput) * medium_ior * medium_ior;
      }
      break;
    }
    // The occlusion map scales all light the point reflects (surface_shading.hpp).
    throughput *= surface.occlusion;
    const vec3 wo = -ray.direction;
    const SurfaceMaterial& material = surface.material;
    const MaterialBsdf bsdf(material, n, meetsFrontFace(*hit_scene, hit, ray.direction),
                            surface.clearcoat_normal);
    // A normal map can lean a reflection below the face, into the relic (where culled back
    // faces would let it out): such reflected directions reflect nothing, for both strategies
    // alike. Transmitted directions go below the face by design.
    const auto reflects = [&](const vec3& wi) { return !surface.normal_mapped || glm::dot(wi, ng) > 0.0f; };

    // Next-event estimation towards the environment, balance heuristic against the BSDF.
    const vec2 u_light = stream.next2D();  // drawn in every mode: the streams stay aligned
    const LightSampling mode = options_.sampling;
    if (mode != LightSampling::kBsdfOnly && bsdf.hasNonDelta()) {
      const EnvironmentSample ls = environment_.sample(u_light, p);
      if (ls.pdf > 0.0f && reflects(ls.direction)) {
        const vec3 f = bsdf.eval(wo, ls.direction);
        if (f.x > 0.0f || f.y > 0.0f || f.z > 0.0f) {
          // A direction into the relic (transmission) meets the relic itself: occluded.
          if (!all.occluded(spawnRay(p, ng, ls.direction))) {
            const float bsdf_pdf = mode == LightSampling::kMis ? bsdf.pdf(wo, ls.direction) : 0.0f;
            radiance += throughput * f * ls.radiance / (ls.pdf + bsdf_pdf);
          }
        }
      }
    }

    // Continue the path by BSDF sampling.
    const auto bs = bsdf.sample(wo, stream.next3D());
    if (!bs || (!bs->transmitted && !reflects(bs->wi))) break;
    ++(bs->dielectric ? dielectric_scatterings : scatterings);
    throughput *= bs->weight;
    if (!(throughput.x > 0.0f || throughput.y > 0.0f || throughput.z > 0.0f)) break;
    if (bs->transmitted && !bsdf.thinWalled()) {
      // Crossing a volume's surface: into it from its front face, out of it from its back.
      in_volume = meetsFrontFace(*hit_scene, hit, ray.direction);
      absorption = in_volume
                       ? attenuationCoefficient(material.attenuation_colour, material.attenuation_distance)
                       : vec3(0.0f);
      medium_ior = in_volume && std::isfinite(material.ior) ? std::max(material.ior, 1.0f) : 1.0f;
    }
    ray = spawnRay(p, ng, bs->wi);
    hit = all.intersect(ray);
    hit_scene = &all;
    if (!hit.hit()) {
      // Leaving an open volume through a hole: its medium ends there (no infinite absorption).
      const vec3 le = environment_.radiance(ray.origin, ray.direction);
      float weight = 1.0f;
      if (!bs->delta) {
        if (mode == LightSampling::kMis) {
          const float light_pdf = environment_.pdf(ray.origin, ray.direction);
          weight = bs->pdf / (bs->pdf + light_pdf);
        } else if (mode == LightSampling::kEnvironmentOnly) {
          weight = 0.0f;
        }
      }
      radiance += throughput * le * weight;
      break;
    }
    if (in_volume) {
      // Beer-Lambert over the segment inside the volume; 0 * a huge coefficient stays 0.
      throughput *= transmittance(absorption, hit.t);
      if (!(throughput.x > 0.0f || throughput.y > 0.0f || throughput.z > 0.0f)) break;
    }
    if (!scene_.isRelic(hit.geometry)) {
      radiance += throughput * scene_.emission(hit);
      break;
    }
  }
  return radiance;
}

ProgressiveRender::ProgressiveRender(const PathTracer& tracer, const CameraModel& camera)
    : tracer_(tracer),
      camera_(camera),
      sum_(static_cast<std::size_t>(camera.width()) * camera.height(), glm::dvec3(0.0)) {}

void ProgressiveRender::addSamples(int spp, bool quiet) {
  if (spp <= 0) return;
  const int w = camera_.width(), h = camera_.height();
  const int tile = tracer_.options().tile_size;
  const int tiles_x = (w + tile - 1) / tile, tiles_y = (h + tile - 1) / tile;
  ProgressReporter progress(std::int64_t(tiles_x) * tiles_y, "Path tracing", quiet);
  std::mutex stats_mutex;
  const float clamp = tracer_.options().firefly_clamp;
  const int first = spp_;
  const std::int64_t nonfinite_before = stats_.nonfinite_dropped;
  const std::int64_t truncated_before = stats_.truncated;
  tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1), [&](const auto& r) {
    PathTracerStats local;
    for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty) {
      for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) {
        for (int y = ty * tile; y < std::min(h, (ty + 1) * tile); ++y) {
          for (int x = tx * tile; x < std::min(w, (tx + 1) * tile); ++x) {
            const std::uint32_t pixel = std::uint32_t(y) * std::uint32_t(w) + std::uint32_t(x);
            glm::dvec3 acc(0.0);
            for (int s = first; s < first + spp; ++s) {
              SampleStream stream(tracer_.options().seed, pixel, std::uint32_t(s));
              const vec2 jitter = stream.next2D();
              const Ray ray = primaryRay(camera_, vec2(x, y) + jitter - 0.5f);
              const RayHit hit = tracer_.scene().relicOnly().intersect(ray);
              vec3 L(0.0f);
              PathRecord record;
              if (hit.hit())
                L = tracer_.traceFromRelic(ray, hit, stream, 1.0f / camera_.intrinsics().fx, &record);
              ++local.samples;
              if (record.truncated) {
                ++local.truncated;
                local.truncated_throughput += double(record.truncated_throughput);
              }
              if (!isFinite(L)) {
                ++local.nonfinite_dropped;
                continue;
              }
              L = glm::max(L, vec3(0.0f));
              const float lum = luminance(L);
              if (clamp > 0.0f && lum > clamp) {
                ++local.clamped;
                local.clamped_energy += double(lum - clamp);
                L *= clamp / lum;
              }
              local.total_energy += double(luminance(L));
              acc += glm::dvec3(L);
            }
            sum_[pixel] += acc;
          }
        }
        progress.update();
      }
    }
    const std::lock_guard lock(stats_mutex);
    stats_.samples += local.samples;
    stats_.nonfinite_dropped += local.nonfinite_dropped;
    stats_.clamped += local.clamped;
    stats_.clamped_energy += local.clamped_energy;
    stats_.total_energy += local.total_energy;
    stats_.truncated += local.truncated;
    stats_.truncated_throughput += local.truncated_throughput;
  });
  spp_ += spp;
  const std::int64_t new_nonfinite = stats_.nonfinite_dropped - nonfinite_before;
  if (new_nonfinite > 0) stats::add("Reflect/Path samples non-finite", new_nonfinite);
  if (stats_.truncated > truncated_before)
    stats::add("Reflect/Path samples stopped by a bounce cap", stats_.truncated - truncated_before);
}

cv::Mat ProgressiveRender::image() const {
  cv::Mat out(camera_.height(), camera_.width(), CV_32FC3, cv::Scalar::all(0));
  if (spp_ == 0) return out;
  for (int y = 0; y < out.rows; ++y)
    for (int x = 0; x < out.cols; ++x) {
      const glm::dvec3 m = sum_[static_cast<std::size_t>(y) * out.cols + x] / double(spp_);
      vec3 v(m);
      if (!isFinite(v)) v = vec3(0.0f);
      setRgb(out, x, y, glm::min(v, vec3(3.0e38f)));
    }
  return out;
}

cv::Mat ProgressiveRender::relicMask() const {
  cv::Mat mask(camera_.height(), camera_.width(), CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (tracer_.scene().relicOnly().intersect(primaryRay(camera_, vec2(x, y))).hit())
        mask.at<uchar>(y, x) = 255;
  return mask;
}

cv::Mat renderPathTraced(const PathTracer& tracer, const CameraModel& camera, int spp, PathTracerStats* stats,
                         bool quiet) {
  ProgressiveRender render(tracer, camera);
  render.addSamples(spp, quiet);
  if (stats) *stats = render.stats();
  return render.image();
}

}  // namespace holo::reference
