// Whether an effect that changes only how a view's rough lobe is sampled shows (internal): its own
// displayed change, measured where it last ran in the view, decides the next frames' plans. Two
// effects take one gate each per view. The axis-aligned filter (axis_aligned_filter.hpp): a
// view's static pass runs it and records the largest change of a displayed sRGB code it made.
// Progressive refinement (progressive_accumulation.hpp): a still view's accumulation runs until it
// holds ProgressiveAccumulation::kMeasuredSets sets and records the largest change of a displayed
// code between set 0 and them. Both measure unrounded codes, any channel, at the exposure the view
// was shown at. While the change is below TracerSettings::effect_min_codes, the view leaves the
// effect off, until a change that could make it show re-checks it: the light (the IBL's source or
// the relic's turn), an exposure more than kExposureStep above the measured one (a brighter
// display moves codes further), the eye more than kEyeDistance from where it was measured, or
// kStaticPasses static passes without it (the eye's drift, a step at a time). The visitors play no
// part: both work on the static shading, which they do not change. Everything it reads is the
// frame's input, so the same frames give the same plans and images.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "holo/core/math.hpp"

namespace holo::reflect {

// The radiance (linear RGB) of a pixel whose rough lobe was filtered, without and with the filter.
struct FilterChange {
  vec3 unfiltered{0.0f};
  vec3 filtered{0.0f};
};

class LobeEffectGate {
 public:
  static constexpr float kEyeDistance = 0.05f;  // metres
  static constexpr float kExposureStep = 1.25f;
  static constexpr int kStaticPasses = 30;

  // The largest displayed change at the last check; infinite when one is due. `reused`: the view's
  // static shading is kept this frame (no static pass to check in), so the last check stands.
  float codes(const vec3& eye, float exposure, std::uint64_t light, bool reused) const {
    if (measured_ && reused) return codes_;
    const bool due = !measured_ || light != light_ || exposure > exposure_ * kExposureStep ||
                     glm::distance(eye, eye_) > kEyeDistance || passes_ >= kStaticPasses;
    return due ? std::numeric_limits<float>::infinity() : codes_;
  }
  // A measurement that spans frames has begun (a refinement restarted): the last one no longer
  // stands, and the effect runs until record().
  void measuring() { measured_ = false; }
  // The effect's largest displayed change, where and under what it was seen.
  void record(float codes, const vec3& eye, float exposure, std::uint64_t light) {
    measured_ = true;
    codes_ = codes;
    eye_ = eye;
    exposure_ = exposure;
    light_ = light;
    passes_ = 0;
  }
  // A static pass without the effect.
  void skipped() { ++passes_; }

 private:
  bool measured_ = false;
  float codes_ = 0.0f;
  vec3 eye_{0.0f};
  float exposure_ = 0.0f;
  std::uint64_t light_ = 0;
  int passes_ = 0;
};

}  // namespace holo::reflect
