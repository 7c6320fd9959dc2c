#include "axis_aligned_filter.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "holo/core/stopwatch.hpp"

namespace holo::reflect {
namespace {

constexpr float kSigmas = 2.5f;          // the radius, in standard deviations of the Gaussian
constexpr float kSameSurfaceCos = 0.9f;  // normals further apart: another surface
// A neighbour further off the pixel's tangent plane than this share of its distance along it (plus
// one footprint) is across a depth edge.
constexpr float kPlaneSlope = 0.5f;

// The weight of neighbour q for centre p (0: another surface).
float weight(const PixelBounce& p, float p_b2, const PixelBounce& q, float q_b2, float footprint) {
  if (!q.rough || glm::dot(p.normal, q.normal) < kSameSurfaceCos) return 0.0f;
  const vec3 d = q.position - p.position;
  const float d2 = glm::dot(d, d);
  const float off_plane = std::abs(glm::dot(p.normal, d));
  if (off_plane > kPlaneSlope * std::sqrt(d2) + footprint) return 0.0f;
  return std::exp(-2.0f * 0.5f * (p_b2 + q_b2) * d2);
}

}  // namespace

float AxisAlignedFilter::brdfBandwidth(float roughness) {
  const float alpha = std::max(roughness * roughness, 1e-3f);
  const float phong_exponent = std::max(2.0f / (alpha * alpha) - 2.0f, 0.0f);
  return 4.27f + 0.15f * phong_exponent;
}

float AxisAlignedFilter::bandwidth(float roughness, float nearest_hit) {
  if (!std::isfinite(nearest_hit) || !(nearest_hit > 0.0f)) return 0.0f;
  return brdfBandwidth(roughness) / nearest_hit;
}

FilterCounts AxisAlignedFilter::apply(const std::vector<PixelBounce>& pixels,
                                      std::vector<LobeBounce>& bounces, int width, int height,
                                      const CameraModel& view) const {
  const Stopwatch clock;
  FilterCounts counts;
  const std::size_t n = std::size_t(width) * std::size_t(height);
  std::vector<float> b2(n, 0.0f), footprint(n, 0.0f);
  std::vector<int> radius(n, 0);
  const float per_pixel = 1.0f / view.intrinsics().fx;  // radians per pixel
  for (std::size_t p = 0; p < n; ++p) {
    if (!pixels[p].rough) continue;
    // z_min of the pixel's own lobe rays (the paper's per-pixel sampling pass), not of the tent's
    // pooled neighbourhood: the least of its 36 rays' distances is the nearest wall's wherever
    // any of them grazes it, which narrows the filter over the whole inside of a bowl. Where none
    // of its own rays met the relic but a neighbour's did (the edge of what the lobe sees), the
    // pooled z_min keeps the filter from spreading that light across the edge.
    const float own = pixels[p].samples.nearest;
    const float b = bandwidth(pixels[p].roughness, std::isfinite(own) ? own : bounces[p].nearest);
    b2[p] = b * b;
    footprint[p] = glm::length(pixels[p].position - view.position()) * per_pixel;
    const float sigma_pixels =
        b > 0.0f ? 1.0f / (2.0f * b * std::max(footprint[p], 1e-9f)) : std::numeric_limits<float>::infinity();
    radius[p] = int(std::min(std::ceil(kSigmas * sigma_pixels), float(kMaxRadius)));
    ++counts.pixels;
  }
  std::atomic<std::uint64_t> taps{0};
  // One pass along the image's X axis (rows) or Y axis (columns).
  const auto pass = [&](const std::vector<LobeBounce>& in, std::vector<LobeBounce>& out, bool dx) {
    const int lines = dx ? height : width, length = dx ? width : height;
    tbb::parallel_for(0, lines, [&](int line) {
      std::uint64_t local = 0;
      for (int s = 0; s < length; ++s) {
        const int x = dx ? s : line, y = dx ? line : s;
        const std::size_t p = std::size_t(y) * std::size_t(width) + std::size_t(x);
        if (!pixels[p].rough) continue;
        LobeBounce sum;
        for (int i = -radius[p]; i <= radius[p]; ++i) {
          const int t = s + i;
          if (t < 0 || t >= length) continue;
          const std::size_t q = p + std::size_t(std::ptrdiff_t(i) * (dx ? 1 : std::ptrdiff_t(width)));
          const float w = i == 0 ? 1.0f : weight(pixels[p], b2[p], pixels[q], b2[q], footprint[p]);
          if (w <= 0.0f) continue;
          sum.add(in[q], w);
          ++local;
        }
        out[p] = sum;
      }
      taps += local;
    });
  };
  std::vector<LobeBounce> along_x(bounces);
  pass(bounces, along_x, true);
  pass(along_x, bounces, false);
  counts.taps = taps.load();
  counts.ms = clock.ms();
  return counts;
}

}  // namespace holo::reflect
