#include "progressive_accumulation.hpp"

#include <bit>

namespace holo::reflect {
namespace {

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace

vec2 stratumOffset(std::uint32_t set, std::size_t pixel, int sample) {
  const std::uint64_t h = mix(std::uint64_t(pixel) * 8u + std::uint64_t(sample) + 0x9e3779b97f4a7c15ull);
  // Sobol's first two dimensions from a point of its own per sample (a (0, 2)-sequence: any 2^k
  // consecutive points from a multiple of 2^k stratify the square into any 2^k equal boxes),
  // digitally shifted per sample.
  std::uint32_t x = 0, y = 0;
  for (std::uint32_t n = set + std::uint32_t(h >> 54), bit = 1u << 31, v = 1u << 31; n;
       n >>= 1, bit >>= 1, v ^= v >> 1)
    if (n & 1u) {
      x |= bit;
      y ^= v;
    }
  x ^= std::uint32_t(h);
  y ^= std::uint32_t(h >> 32);
  return vec2(float(x >> 8) * (1.0f / 16777216.0f), float(y >> 8) * (1.0f / 16777216.0f));
}

std::uint64_t foregroundSignature(const VoxelGrid& grid) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < grid.occupiedCount(); ++i) {
    const VoxelSample& s = grid.sample(std::int32_t(i));
    std::uint64_t h = mix((std::uint64_t(s.camera) << 32) | (std::uint64_t(s.x) << 16) | s.y);
    for (float f : {s.radiance.x, s.radiance.y, s.radiance.z, s.weight})
      h = mix(h ^ std::bit_cast<std::uint32_t>(f));
    sum += h;  // a sum: the same whatever order the points were binned in
  }
  return mix(sum ^ std::uint64_t(grid.occupiedCount()));
}

void ProgressiveAccumulation::restart(const std::vector<PixelBounce>& bounces, std::uint64_t foreground) {
  pixels_.clear();
  for (std::size_t p = 0; p < bounces.size(); ++p)
    if (bounces[p].rough) pixels_.push_back(std::uint32_t(p));
  sets_ = 1;
  foreground_ = foreground;
}

RefinementStep ProgressiveAccumulation::advance(const StaticShading& shading_pass, const HitPointBuffer& hits,
                                                const CameraModel& view, std::uint64_t foreground,
                                                std::uint32_t max_sets, std::vector<SplitSumShading>& shading,
                                                std::vector<WalkRay>& walk_rays,
                                                std::vector<PixelBounce>& bounces, cv::Mat& hdr,
                                                const AxisAlignedFilter* filter) {
  RefinementStep step;
  const bool still = foreground == foreground_;
  foreground_ = foreground;
  std::uint32_t set = 0;
  if (!still) {
    step.reset = sets_ > 1;
    if (!step.reset) {  // set 0 alone already: nothing to undo
      step.sets = sets_;
      return step;
    }
    for (std::uint32_t p : pixels_) bounces[p].samples = LobeBounce{};
    sets_ = 0;
  } else if (sets_ >= max_sets || pixels_.empty()) {
    step.sets = sets_;
    return step;
  } else {
    set = sets_;
  }
  hdr = hdr.clone();
  step.samples = shading_pass.reshadeLobes(
      hits, view, pixels_, [set](std::size_t pixel, int sample) { return stratumOffset(set, pixel, sample); },
      shading, walk_rays, bounces, hdr, filter, &step.filtered);
  sets_ += 1;
  step.sets = sets_;
  step.image_changed = true;
  return step;
}

}  // namespace holo::reflect
