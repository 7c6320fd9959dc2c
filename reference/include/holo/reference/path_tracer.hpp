// Evaluation only: a reference for measuring the appliance's renderer, never linked by it
// (reference/CMakeLists.txt).
// Monte Carlo path tracer: the ground truth of the evaluation (docs/architecture.md, paper Sec. 4).
//
// GT definition: a camera ray sees only the relic (pixels that miss it are 0: the pyramid's
// monitors show the relic alone); from the relic, paths bounce on the relic's glTF BSDF
// (dielectric.hpp's MaterialBsdf: metallic-roughness, clearcoat, specular, and glass -
// transmission, refraction, total internal reflection) up to max_bounces times plus up to
// max_dielectric_bounces events on the glass lobe, reach emitters (hall, visitors: diffuse
// emitters, their radiance is Material::emission, they do not scatter) or escape to the
// environment. Every relic vertex adds the relic's own emission, the one a path reaches after its
// last scattering included. The relic's surface at every vertex comes from surface_shading.hpp
// (textures filtered at the footprint of the camera ray's cone, normal maps, occlusion scaling the
// light the vertex reflects, emissive textures); cut-out (MASK) texels and culled back faces are
// not hit by any ray, and BLEND surfaces are stopped at with probability alpha (stochastic
// transparency). A path tracks the medium it is in: entering a volume material
// (KHR_materials_volume, thickness > 0) through a front face (glTF winding) it is absorbed by
// Beer-Lambert (attenuationColor/Distance) until it leaves through a back face; a thin-walled
// material is crossed without bending or absorption. A path that leaves an open volume through a
// hole leaves its medium. The tracer gathers radiance, so a refraction scales it by (n_o/n_i)^2
// (dielectric.hpp). At every non-delta
// relic vertex the environment is sampled (next-event estimation through its importance
// distribution, shadowed by all geometry) and combined with BSDF sampling by the balance
// heuristic (delta-path-tracing paper Sec. 3.2); emitters are reached by BSDF sampling only.
// No Russian roulette: the estimator is exact for the bounce budget.
//
// Samples come from a seeded per-pixel Owen-scrambled Sobol stream (sampler.hpp), so a render is
// bit-identical for a seed whatever the thread count, and passes accumulate progressively.
// A non-finite path sample is dropped and counted; the optional firefly clamp limits each path
// sample's luminance and reports the energy it removed. Output: linear HDR CV_32FC3 BGR.
#pragma once

#include <cstdint>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/reference/sampler.hpp"
#include "holo/reflect/environment.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reference {

// The path tracer's version, part of every cached ground truth's key (eval/ground_truth_cache.hpp).
// Bump it in the change that alters what the tracer renders for the same scene, view, spp and seed
// (its estimators, BSDF, sampler, defaults of PathTracerOptions), so cached truths are rendered again.
// 2: glass, clearcoat and KHR_materials_specular's colour (dielectric.hpp), media; every texture
//    map (surface_shading.hpp).
// 3: the opaque dielectric's F0 from the IOR and the specular colour (texture included).
inline constexpr int kPathTracerVersion = 3;

// Which estimators a path vertex combines. Only kMis is the ground truth; the single-strategy
// modes exist to check it (all three converge to the same image, with different noise).
enum class LightSampling {
  kMis,              // environment NEE + BSDF sampling, balance heuristic
  kBsdfOnly,         // BSDF sampling alone (environment reached only by escaping paths)
  kEnvironmentOnly,  // environment NEE alone (escaping non-delta BSDF paths add nothing)
};

struct PathTracerOptions {
  // Scattering events on the relic per path, >= 1 (less is raised to 1): what a path meets
  // after its max_bounces-th scattering (environment, emitter, relic emission) still counts, so
  // 1 is direct lighting and light reflected k times is kept for k <= max_bounces. 5: its bias
  // on the tripod's bowl is in docs/reflect.md.
  int max_bounces = 5;
  // Scatterings on the glass lobe (reflection or refraction of a transmissive material) per path,
  // counted apart from max_bounces: a ray through a glass vase crosses four surfaces, one in a
  // brilliant reflects totally many times. >= 1. The crystal (gallery, face 2, 128^2 x 64 spp)
  // loses 0.0116 per sample of an environment of 1 at a cap of 16, 0.00125 at 64, 1.6e-6 at 256
  // for 7% more time (docs/reflect.md).
  int max_dielectric_bounces = 256;
  std::uint64_t seed = 1;
  float firefly_clamp = 0.0f;  // max luminance of one path sample; 0 = off (unbiased)
  int tile_size = 16;          // pixels, for the oneTBB tiles
  LightSampling sampling = LightSampling::kMis;
};

struct PathTracerStats {
  std::int64_t samples = 0;            // path samples taken so far
  std::int64_t nonfinite_dropped = 0;  // path samples that were NaN/Inf (counted, contribute 0)
  std::int64_t clamped = 0;            // path samples the firefly clamp touched
  double clamped_energy = 0;           // luminance removed by the clamp, summed over samples
  double total_energy = 0;             // luminance kept, summed over samples
  // Paths cut by a bounce cap (a ray trapped by total internal reflection), and the luminance of
  // their throughput summed (times n^2 inside a medium of IOR n: what it would carry back into
  // air): the energy the caps dropped from an environment of radiance 1.
  std::int64_t truncated = 0;
  double truncated_throughput = 0;
  double clampedFraction() const {
    const double all = clamped_energy + total_energy;
    return all > 0 ? clamped_energy / all : 0.0;
  }
};

// What one path did, for the statistics.
struct PathRecord {
  bool truncated = false;          // stopped by max_bounces or max_dielectric_bounces
  float truncated_throughput = 0;  // luminance of its throughput there, times the medium's IOR^2
};

class PathTracer {
 public:
  // The scene and environment must outlive the tracer.
  PathTracer(const reflect::RenderScene& scene, const reflect::Environment& environment,
             PathTracerOptions options = {});

  // One path sample of the radiance arriving along `ray` after it has hit the relic; the
  // samples come from `stream`. pixel_spread (radians, 1 / fx for a camera ray): the pixel's
  // footprint is the path length times it (0: textures at their sharpest level). `record`, when
  // given, says whether a bounce cap stopped the path. Exposed for tests and for hybrid renderers
  // that trace from the relic.
  vec3 traceFromRelic(const Ray& ray, const RayHit& relic_hit, SampleStream& stream,
                      float pixel_spread = 0.0f, PathRecord* record = nullptr) const;

  const PathTracerOptions& options() const { return options_; }
  const reflect::RenderScene& scene() const { return scene_; }
  const reflect::Environment& environment() const { return environment_; }

 private:
  const reflect::RenderScene& scene_;
  const reflect::Environment& environment_;
  PathTracerOptions options_;
};

// Progressive accumulation of one camera view: each addSamples() call continues the same
// per-pixel sample sequences, so N passes of k samples equal one pass of N*k.
class ProgressiveRender {
 public:
  ProgressiveRender(const PathTracer& tracer, const CameraModel& camera);
  // Adds `spp` samples to every pixel (oneTBB over tiles). Shows progress unless quiet.
  void addSamples(int spp, bool quiet = true);
  cv::Mat image() const;  // mean radiance, CV_32FC3 BGR, always finite
  int samplesPerPixel() const { return spp_; }
  const PathTracerStats& stats() const { return stats_; }
  // Relic coverage: 255 where the pixel centre's primary ray hits the relic.
  cv::Mat relicMask() const;

 private:
  const PathTracer& tracer_;
  CameraModel camera_;
  std::vector<glm::dvec3> sum_;
  int spp_ = 0;
  PathTracerStats stats_;
};

// Convenience: a full render at `spp` samples per pixel.
cv::Mat renderPathTraced(const PathTracer& tracer, const CameraModel& camera, int spp,
                         PathTracerStats* stats = nullptr, bool quiet = true);

}  // namespace holo::reference
