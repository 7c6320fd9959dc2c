#include "holo/reflect/frame_renderer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/composition.hpp"
#include "holo/reflect/dfg_table.hpp"
#include "holo/reflect/hit_points.hpp"
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

// The split-sum shading of PrefilteredIbl::shade, kept in two parts so the foreground can replace
// the environment radiance in the specular part: radiance = specular_scale * L + diffuse.
struct Shading {
  vec3 specular_scale{0.0f};  // F0 * A + F90 * B (DFG table)
  vec3 diffuse{0.0f};         // SH irradiance diffuse, radiance
  vec3 environment{0.0f};     // prefiltered environment radiance along the reflected direction
};

Shading shadeStatic(const PrefilteredIbl& ibl, const HitPoint& h) {
  Shading s;
  const float nv = glm::dot(h.normal, h.to_viewer);
  if (!(nv > 0.0f)) return s;
  const SurfaceMaterial& m = h.material;
  const float metallic = std::clamp(m.metallic, 0.0f, 1.0f);
  const float spec = std::clamp(m.specular, 0.0f, 1.0f);
  const vec3 base = glm::clamp(m.base_color, vec3(0.0f), vec3(1.0f));
  const vec2 ab = dfg(nv, m.roughness);
  const vec3 f0 = (1.0f - metallic) * kDielectricF0 * spec + metallic * base;
  const float f90 = (1.0f - metallic) * spec + metallic;
  s.specular_scale = f0 * ab.x + f90 * ab.y;
  s.environment = ibl.specular(h.reflected, m.roughness);
  const float dielectric_reflectance = kDielectricF0 * spec * ab.x + spec * ab.y;
  s.diffuse = (1.0f - metallic) * (1.0f - dielectric_reflectance) * base * ibl.irradiance(h.normal) / kPi;
  return s;
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
  grid.validate(src + " grid");
}

FrameRenderer::FrameRenderer(const RenderScene& scene, const PrefilteredIbl& ibl, TracerSettings settings)
    : scene_(scene), ibl_(ibl), settings_((settings.validate(), settings)), grid_(settings_.grid) {
  for (const Material& m : scene_.relic().materials)
    if (m.roughness < kGlossyRoughnessLimit || m.metallic_roughness_texture >= 0) relic_glossy_ = true;
  if (scene_.relic().materials.empty()) relic_glossy_ = true;  // default material: be safe
}

EffectPlan FrameRenderer::plan(const depthfilter::ForegroundCloud& cloud,
                               const std::vector<ForegroundCameraImage>& cameras) const {
  EffectInputs in;
  in.foreground_enabled = settings_.foreground_enabled;
  in.relic_empty = scene_.relic().triangleCount() == 0;
  in.relic_glossy = relic_glossy_;
  in.foreground_points = cloud.points.size();
  in.cameras = cameras.size();
  in.relic_bounds = scene_.relicBounds();
  if (!cloud.empty()) in.foreground_bounds = cloud.bounds();
  in.max_reflection_distance = settings_.max_reflection_distance;
  return planEffects(in);
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
  pyramids_.clear();
  if (result.plan.has(Pass::Pyramids)) {
    PassTimer t(result.frame_timings, Pass::Pyramids);
    // A camera without an image this frame (it dropped out) gets an empty pyramid: its points
    // are ignored, as the header promises, and the other cameras still give reflections.
    for (const ForegroundCameraImage& c : cameras)
      pyramids_.push_back(c.colour_bgr.empty()
                              ? ForegroundPyramid()
                              : ForegroundPyramid(c.colour_bgr, c.mask, settings_.pyramid_levels));
  }
  for (const CameraModel& v : views) result.views.push_back(renderView(result.plan, cameras, v));
  return result;
}

ViewImages FrameRenderer::renderView(const EffectPlan& plan,
                                     const std::vector<ForegroundCameraImage>& cameras,
                                     const CameraModel& view) const {
  ViewImages out;
  const int w = view.width(), h = view.height();
  out.hdr = cv::Mat(h, w, CV_32FC3, cv::Scalar::all(0));
  out.weight = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
  out.coverage = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
  if (plan.has(Pass::HitPoints)) {
    HitPointBuffer hits;
    {
      PassTimer t(out.timings, Pass::HitPoints);
      hits = traceHitPoints(scene_, view, settings_.aa_samples);
    }
    const std::size_t n = hits.hits.size();
    std::vector<Shading> shading(n);
    {
      PassTimer t(out.timings, Pass::StaticReflections);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i)
          if (hits.valid[i]) shading[i] = shadeStatic(ibl_, hits.hits[i]);
      });
    }
    std::vector<ForegroundSample> fg(n);
    if (plan.has(Pass::ForegroundWalk)) {
      PassTimer t(out.timings, Pass::ForegroundWalk);
      std::atomic<std::uint64_t> walked{0}, found{0};
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
        std::uint64_t local_walked = 0, local_found = 0;
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
          if (!hits.valid[i]) continue;
          const HitPoint& hp = hits.hits[i];
          ++local_walked;
          const Ray ray{hp.position + hp.normal * settings_.ray_offset, hp.reflected};
          const VoxelHit vh = firstOccupiedVoxel(grid_, ray, settings_.max_reflection_distance);
          if (!vh.hit()) continue;
          const depthfilter::VoxelSample& vs = grid_.sample(vh.sample);
          if (vs.camera >= pyramids_.size() || pyramids_[vs.camera].empty()) continue;
          const CameraModel& cam = cameras[vs.camera].camera;
          // The point the ray reaches: half a voxel into the one it entered.
          const vec3 p = ray.origin + ray.direction * (vh.t + 0.5f * grid_.voxelSize());
          float depth = 0.0f;
          const std::optional<vec2> px = cam.project(p, &depth);
          const vec2 pixel = px ? *px : vec2(vs.x, vs.y);
          const float level = foregroundLevel(hp.material.roughness, vh.t, glm::length(p - cam.position()),
                                              cam.intrinsics().fx, settings_.pyramid_levels);
          fg[i] = pyramids_[vs.camera].sample(pixel, level);
          ++local_found;
        }
        walked += local_walked;
        found += local_found;
      });
      out.walked_rays = walked;
      out.foreground_hits = found;
    }
    {
      // Composition (or, without foreground, the static result alone) and anti-aliasing: the
      // mean over sub-samples, misses black.
      PassTimer t(out.timings, plan.has(Pass::Composition) ? Pass::Composition : Pass::StaticReflections);
      const float inv_s = 1.0f / float(hits.samples);
      tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
          for (int x = 0; x < w; ++x) {
            vec3 sum(0.0f);
            float wsum = 0.0f;
            for (int s = 0; s < hits.samples; ++s) {
              const std::size_t i = hits.index(x, y, s);
              if (!hits.valid[i]) continue;
              const Shading& sh = shading[i];
              const vec3 psi_s = sh.specular_scale * sh.environment;
              const vec3 psi_d = sh.specular_scale * fg[i].radiance;
              sum += composeReflection(psi_d, psi_s, fg[i].weight) +
                     composeReflection(sh.diffuse, vec3(0.0f), 1.0f);
              wsum += fg[i].weight;
            }
            setRgb(out.hdr, x, y, sum * inv_s);
            out.weight.at<float>(y, x) = std::clamp(wsum * inv_s, 0.0f, 1.0f);
            out.coverage.at<float>(y, x) = hits.coverage(x, y);
          }
      });
    }
  }
  {
    PassTimer t(out.timings, Pass::ToneMap);
    out.exposure = settings_.exposure > 0.0f ? settings_.exposure : autoExposure(out.hdr);
    out.display = toneMap(out.hdr, out.exposure);
  }
  return out;
}

}  // namespace holo::reflect
