#include "refraction_anchors.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace holo::reflect {
namespace {

// Where a sample may take its anchors' blend (refraction_anchors.hpp): the same smooth piece of the
// relic (normals within ~25 degrees, the anchor within ~11 degrees of the sample's tangent
// plane) and the same light inside (exit directions within ~8 degrees; ~2 degrees for an anchor
// blending the coarse lattice's, 4 pixels apart: wider bounds there cost measurable error).
constexpr float kAnchorNormalCos = 0.9f;
constexpr float kAnchorPlaneSine = 0.2f;
constexpr float kAnchorExitCos = 0.99f;
constexpr float kCoarseExitCos = 0.9994f;

// Where the anchors' walks agree (blendWalks): mask weights and premultiplied luminances within
// this share of the brightest.
constexpr float kWalkAgreement = 0.1f;

// Which sample of pixel p is its anchor: the centre where it was traced, else the first valid
// sub-sample (Full anti-aliasing traces no centres); hits.hits.size() when none is transmissive.
std::size_t anchorSample(const HitPointBuffer& hits, std::size_t p) {
  if (hits.valid[p] && hits.hits[p].gltf && hits.hits[p].gltf->transmissive()) return p;
  if (hits.first_sub[p] == HitPointBuffer::kCentreOnly) return hits.hits.size();
  for (std::size_t i = hits.first_sub[p]; i < hits.first_sub[p] + 4; ++i)
    if (hits.valid[i] && hits.hits[i].gltf && hits.hits[i].gltf->transmissive()) return i;
  return hits.hits.size();
}

}  // namespace

AnchorGrid anchorGrid(const HitPointBuffer& hits, int stride) {
  AnchorGrid grid;
  grid.stride = stride;
  grid.width = stride > 1 ? (hits.width - 1) / stride + 1 : 0;
  grid.height = stride > 1 ? (hits.height - 1) / stride + 1 : 0;
  return grid;
}

bool sameSurface(const RefractionAnchor& a, const HitPoint& hp) {
  if (a.material != hp.gltf || glm::dot(a.normal, hp.normal) < kAnchorNormalCos) return false;
  const vec3 d = a.position - hp.position;
  return std::abs(glm::dot(d, hp.normal)) <= kAnchorPlaneSine * glm::length(d);
}

Blend blendAnchors(const std::vector<RefractionAnchor>& anchors, const AnchorGrid& grid, int step,
                   const HitPoint& hp, const vec2& at, TransmittedPath& out, WalkSource& source) {
  const vec2 u = at / float(grid.stride * step);
  const vec2 cell = glm::floor(u), f = u - cell;
  const RefractionAnchor* used[4];
  float weights[4];
  std::uint32_t indices[4];
  int n = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const float w = (i ? f.x : 1.0f - f.x) * (j ? f.y : 1.0f - f.y);
      if (!(w > 1e-6f)) continue;
      const int ax = (int(cell.x) + i) * step, ay = (int(cell.y) + j) * step;
      if (ax < 0 || ay < 0 || ax >= grid.width || ay >= grid.height) return Blend::NotBlended;
      const std::size_t index = std::size_t(ay) * std::size_t(grid.width) + std::size_t(ax);
      const RefractionAnchor& a = anchors[index];
      if (!sameSurface(a, hp)) return Blend::NotBlended;
      if (n > 0 && (a.unit.events != used[0]->unit.events || a.unit.exited != used[0]->unit.exited))
        return Blend::EventsDiffer;
      if (n > 0 && glm::dot(a.unit.exit_direction, used[0]->unit.exit_direction) <
                       (step > 1 ? kCoarseExitCos : kAnchorExitCos))
        return Blend::NotBlended;
      used[n] = &a;
      indices[n] = std::uint32_t(index);
      weights[n++] = w;
    }
  if (n == 0) return Blend::NotBlended;
  float total = 0.0f;
  for (int k = 0; k < n; ++k) total += weights[k];
  out = TransmittedPath{};
  vec3 direction(0.0f);
  for (int k = 0; k < n; ++k) {
    const TransmittedPath& a = used[k]->unit;
    const float w = weights[k] / total;
    out.scale += w * a.scale;
    out.resolved += w * a.resolved;
    out.reflected += w * a.reflected;
    out.exit_position += w * a.exit_position;
    direction += w * a.exit_direction;
    out.roughness += w * a.roughness;
  }
  const float length = glm::length(direction);
  if (!(length > 1e-6f)) return Blend::NotBlended;
  out.exit_direction = direction / length;
  out.exited = used[0]->unit.exited;
  out.events = used[0]->unit.events;
  source = WalkSource{};
  source.anchors = std::uint8_t(n);
  for (int k = 0; k < n; ++k) {
    source.anchor[k] = indices[k];
    source.weight[k] = weights[k] / total;
  }
  return Blend::Blended;
}

const RefractionAnchor* anchorTracedAt(const std::vector<RefractionAnchor>& anchors, const AnchorGrid& grid,
                                       const HitPointBuffer& hits, std::size_t p, std::size_t i) {
  if (grid.stride <= 1) return nullptr;
  const int x = int(p % std::size_t(hits.width)), y = int(p / std::size_t(hits.width));
  if (x % grid.stride != 0 || y % grid.stride != 0 || anchorSample(hits, p) != i) return nullptr;
  const RefractionAnchor& a =
      anchors[std::size_t(y / grid.stride) * std::size_t(grid.width) + std::size_t(x / grid.stride)];
  return a.material && a.source.anchors == 0 ? &a : nullptr;
}

std::uint64_t traceAnchors(const RenderScene& scene, const PrefilteredIbl& ibl,
                           const TracerSettings& settings, int depth, const HitPointBuffer& hits,
                           const AnchorGrid& grid, std::vector<RefractionAnchor>& anchors) {
  anchors.assign(grid.size(), RefractionAnchor{});
  std::atomic<std::uint64_t> rays{0};
  const int stride = grid.stride;
  const std::vector<vec2> pattern = subsamplePattern(4);
  for (int round = 0; stride > 1 && round < 2; ++round)
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, hits.covered.size(), 256),
        [&](const tbb::blocked_range<std::size_t>& r) {
          std::uint64_t local_rays = 0;
          for (std::size_t k = r.begin(); k < r.end(); ++k) {
            const std::size_t p = hits.covered[k];
            const int x = int(p % std::size_t(hits.width)), y = int(p / std::size_t(hits.width));
            if (x % stride != 0 || y % stride != 0) continue;
            const int gx = x / stride, gy = y / stride;
            if ((gx % 2 == 0 && gy % 2 == 0) != (round == 0)) continue;
            const std::size_t i = anchorSample(hits, p);
            if (i == hits.hits.size()) continue;
            const HitPoint& hp = hits.hits[i];
            RefractionAnchor& a = anchors[std::size_t(gy) * std::size_t(grid.width) + std::size_t(gx)];
            a.position = hp.position;
            a.normal = hp.normal;
            a.material = hp.gltf;
            const vec2 at = vec2(float(x), float(y)) + (i == p ? vec2(0.0f) : pattern[i - hits.first_sub[p]]);
            a.source = WalkSource{};
            if (round == 1 && blendAnchors(anchors, grid, 2, hp, at, a.unit, a.source) == Blend::Blended)
              continue;
            a.unit = traceTransmissionPerUnitEntry(scene, ibl, settings, depth, hp.position, hp.normal,
                                                   -hp.to_viewer, *hp.gltf, &hp.material, nullptr);
            local_rays += a.unit.rays;
          }
          rays += local_rays;
        });
  return rays.load();
}

AnchorExits anchorExits(const std::vector<RefractionAnchor>& anchors) {
  AnchorExits exits;
  for (std::size_t k = 0; k < anchors.size(); ++k) {
    const RefractionAnchor& a = anchors[k];
    if (!a.material || !a.unit.exited) continue;
    (a.source.anchors > 0 ? exits.blended : exits.traced).push_back(std::uint32_t(k));
  }
  return exits;
}

std::uint64_t walkAnchors(const std::vector<RefractionAnchor>& anchors, const AnchorExits& exits,
                          const ForegroundWalk& walk, std::vector<ForegroundSample>& anchor_fg) {
  std::atomic<std::uint64_t> walked{0};
  anchor_fg.assign(anchors.size(), ForegroundSample{});
  for (const std::vector<std::uint32_t>* round : {&exits.traced, &exits.blended})
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, round->size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        std::uint64_t local = 0;
                        for (std::size_t n = r.begin(); n < r.end(); ++n) {
                          const std::size_t k = (*round)[n];
                          const RefractionAnchor& a = anchors[k];
                          if (a.source.anchors > 0 && blendWalks(anchor_fg, a.source, anchor_fg[k])) continue;
                          walk.walk(a.unit.exit_position, a.unit.exit_direction, a.unit.exit_direction,
                                    a.unit.roughness, anchor_fg[k]);
                          ++local;
                        }
                        walked += local;
                      });
  return walked.load();
}

bool blendWalks(const std::vector<ForegroundSample>& anchor_fg, const WalkSource& source,
                ForegroundSample& out) {
  float w_lo = 1.0f, w_hi = 0.0f, l_lo = 0.0f, l_hi = 0.0f;
  vec3 radiance(0.0f);
  float weight = 0.0f;
  for (int a = 0; a < source.anchors; ++a) {
    const ForegroundSample& s = anchor_fg[source.anchor[a]];
    const float l = s.weight * luminance(s.radiance);
    w_lo = std::min(w_lo, s.weight);
    w_hi = std::max(w_hi, s.weight);
    l_lo = a == 0 ? l : std::min(l_lo, l);
    l_hi = a == 0 ? l : std::max(l_hi, l);
    radiance += source.weight[a] * s.weight * s.radiance;
    weight += source.weight[a] * s.weight;
  }
  if (w_hi - w_lo > kWalkAgreement || l_hi - l_lo > kWalkAgreement * l_hi) return false;
  out.weight = weight;
  out.radiance = weight > 0.0f ? radiance / weight : vec3(0.0f);
  return true;
}

}  // namespace holo::reflect
