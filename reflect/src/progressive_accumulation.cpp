#include "progressive_accumulation.hpp"

#include <algorithm>
#include <bit>

#include "holo/core/image.hpp"
#include "holo/reflect/tone_map.hpp"
#include "lobe_sample_sets.hpp"

namespace holo::reflect {
std::uint64_t foregroundSignature(const VoxelGrid& grid) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < grid.occupiedCount(); ++i) {
    const VoxelSample& s = grid.sample(std::int32_t(i));
    std::uint64_t h = splitMixFinaliser((std::uint64_t(s.camera) << 32) | (std::uint64_t(s.x) << 16) | s.y);
    for (float f : {s.radiance.x, s.radiance.y, s.radiance.z, s.weight})
      h = splitMixFinaliser(h ^ std::bit_cast<std::uint32_t>(f));
    sum += h;  // a sum: the same whatever order the points were binned in
  }
  return splitMixFinaliser(sum ^ std::uint64_t(grid.occupiedCount()));
}

void ProgressiveAccumulation::restart(const std::vector<PixelBounce>& bounces, const cv::Mat& hdr,
                                      std::uint64_t foreground) {
  pixels_.clear();
  first_.clear();
  for (std::size_t p = 0; p < bounces.size(); ++p)
    if (bounces[p].rough) {
      pixels_.push_back(std::uint32_t(p));
      first_.push_back(rgbAt(hdr, int(p % std::size_t(hdr.cols)), int(p / std::size_t(hdr.cols))));
    }
  sets_ = 1;
  foreground_ = foreground;
}

void ProgressiveAccumulation::stop() {
  pixels_.clear();
  first_.clear();
  sets_ = 0;
}

float ProgressiveAccumulation::largestChange(const cv::Mat& hdr, float exposure) const {
  float codes = 0.0f;
  for (std::size_t k = 0; k < pixels_.size(); ++k) {
    const std::size_t p = pixels_[k];
    const vec3 now = rgbAt(hdr, int(p % std::size_t(hdr.cols)), int(p / std::size_t(hdr.cols)));
    codes = std::max(codes,
                     maxComponent(glm::abs(toneMapCodes(now, exposure) - toneMapCodes(first_[k], exposure))));
  }
  return codes;
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
