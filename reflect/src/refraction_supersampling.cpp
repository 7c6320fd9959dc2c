#include "refraction_supersampling.hpp"

#include <algorithm>

#include "holo/reflect/hit_points.hpp"
#include "layer_inputs.hpp"

namespace holo::reflect {
namespace {

// The radiance a path brings to its sample before the visitors: the IBL along its exit and what
// it read on the way.
float transmittedLight(const TransmittedPath& path) {
  return luminance(path.scale * path.environment + path.resolved);
}

}  // namespace

RefractionSupersampling::RefractionSupersampling(const RenderScene& scene, const PrefilteredIbl& ibl,
                                                 const TracerSettings& settings, int depth)
    : scene_(scene), ibl_(ibl), settings_(settings), depth_(depth) {
  // 5% of the hall's mean radiance (its irradiance over the six axes, / pi): darker light shows
  // no contrast after the tone map, whatever the ratio.
  constexpr vec3 kAxes[3] = {vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), vec3(0.0f, 0.0f, 1.0f)};
  float mean = 0.0f;
  for (const vec3& axis : kAxes) mean += luminance(ibl.irradiance(axis) + ibl.irradiance(-axis));
  dark_ = 0.05f * mean / (6.0f * kPi);
}

bool RefractionSupersampling::sparkles(const TransmittedPath (&paths)[4], const bool (&transmits)[4]) const {
  const float contrast = settings_.refraction_supersample_contrast;
  if (!(contrast > 0.0f)) return false;
  float lo = 0.0f, hi = 0.0f;
  int n = 0;
  for (int s = 0; s < 4; ++s) {
    if (!transmits[s]) continue;
    const float light = transmittedLight(paths[s]);
    lo = n == 0 ? light : std::min(lo, light);
    hi = n == 0 ? light : std::max(hi, light);
    ++n;
  }
  return n >= 2 && hi + dark_ > contrast * (lo + dark_);
}

std::uint64_t RefractionSupersampling::supersample(const CameraModel& view, const vec2& centre,
                                                   const vec2& offset, const TransmittedPath& own,
                                                   SupersampledPaths& more) const {
  more.count = 0;
  std::uint64_t rays = 0;
  constexpr int n = SupersampledPaths::kGrid;
  const vec2 quarter(offset.x < 0.0f ? -0.25f : 0.25f, offset.y < 0.0f ? -0.25f : 0.25f);
  for (int gy = 0; gy < n; ++gy)
    for (int gx = 0; gx < n; ++gx) {
      const vec2 at = quarter + 0.5f * (vec2(float(gx), float(gy)) + 0.5f) / float(n) - 0.25f;
      HitPoint hp;
      ++rays;
      if (!traceHitPoint(scene_, view, centre + at, hp) || !hp.gltf || !(hp.gltf->transmission > 0.0f))
        continue;
      more.paths[more.count] = traceTransmission(scene_, ibl_, settings_, depth_, hp.position, hp.normal,
                                                 -hp.to_viewer, *hp.gltf, &hp.material);
      rays += more.paths[more.count++].rays;
    }
  if (more.count == 0) more.paths[more.count++] = own;
  return rays;
}

TransmittedPath meanPath(const SupersampledPaths& more) {
  TransmittedPath mean = more.paths[0];
  mean.scale = mean.resolved = mean.reflected = vec3(0.0f);
  vec3 seen(0.0f);
  for (int k = 0; k < more.count; ++k) {
    const TransmittedPath& path = more.paths[k];
    mean.scale += path.scale;
    seen += path.scale * path.environment;
    mean.resolved += path.resolved;
    mean.reflected += path.reflected;
    mean.exited = mean.exited || path.exited;
  }
  const float inv = 1.0f / float(more.count);
  mean.scale *= inv;
  mean.resolved *= inv;
  mean.reflected *= inv;
  for (int c = 0; c < 3; ++c)
    mean.environment[c] = mean.scale[c] > 0.0f ? seen[c] * inv / mean.scale[c] : 0.0f;
  return mean;
}

std::uint64_t walkSupersampledPaths(const SupersampledPaths& more, const ForegroundWalk& walk,
                                    ForegroundSample& out) {
  vec3 scale(0.0f), seen(0.0f);
  bool visitors = false;
  std::uint64_t walked = 0;
  for (int k = 0; k < more.count; ++k) {
    const TransmittedPath& path = more.paths[k];
    scale += path.scale;
    if (!path.exited || !(luminance(path.scale) > 0.0f)) continue;
    ForegroundSample fg;
    walk.walk(path.exit_position, path.exit_direction, path.exit_direction, path.roughness, fg);
    ++walked;
    const float w = clamp01(fg.weight);
    seen += path.scale * ((1.0f - w) * path.environment + w * fg.radiance);
    visitors = visitors || w > 0.0f;
  }
  out = ForegroundSample{};
  if (!visitors) return walked;
  out.weight = 1.0f;
  for (int c = 0; c < 3; ++c) out.radiance[c] = scale[c] > 0.0f ? seen[c] / scale[c] : 0.0f;
  return walked;
}

}  // namespace holo::reflect
