#include "holo/reflect/hit_points.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "holo/core/error.hpp"
#include "holo/reflect/view.hpp"

namespace holo::reflect {

std::vector<vec2> subsamplePattern(int samples) {
  if (samples == 1) return {vec2(0.0f)};
  if (samples == 4)  // rotated grid: distinct x and y offsets catch near-axis edges
    return {vec2(-0.125f, -0.375f), vec2(0.375f, -0.125f), vec2(0.125f, 0.375f), vec2(-0.375f, 0.125f)};
  throw InputError("tracer settings", "aa_samples", "1 or 4", std::to_string(samples));
}

float HitPointBuffer::coverage(int x, int y) const {
  int n = 0;
  for (int s = 0; s < samples; ++s) n += valid[index(x, y, s)];
  return float(n) / float(samples);
}

HitPointBuffer traceHitPoints(const RenderScene& scene, const CameraModel& view, int samples) {
  const std::vector<vec2> pattern = subsamplePattern(samples);
  HitPointBuffer buf;
  buf.width = view.width();
  buf.height = view.height();
  buf.samples = samples;
  const std::size_t n = std::size_t(buf.width) * std::size_t(buf.height) * std::size_t(samples);
  buf.hits.resize(n);
  buf.valid.assign(n, 0);
  const RayScene& relic = scene.relicOnly();
  tbb::parallel_for(tbb::blocked_range<int>(0, buf.height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < buf.width; ++x)
        for (int s = 0; s < samples; ++s) {
          const Ray ray = primaryRay(view, vec2(float(x), float(y)) + pattern[std::size_t(s)]);
          const RayHit hit = relic.intersect(ray);
          if (!hit.hit()) continue;
          HitPoint& h = buf.hits[buf.index(x, y, s)];
          h.position = relic.position(ray, hit);
          h.normal = relic.shadingNormal(hit, ray.direction);
          h.to_viewer = -ray.direction;
          h.reflected = glm::reflect(ray.direction, h.normal);
          h.material = scene.relicMaterial(hit, relic);
          if (!isFinite(h.position) || !isFinite(h.normal) || !isFinite(h.reflected)) continue;
          buf.valid[buf.index(x, y, s)] = 1;
        }
  });
  return buf;
}

}  // namespace holo::reflect
