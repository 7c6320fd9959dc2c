#include <gtest/gtest.h>
#include <cmath>
#include <limits>

#include "holo/core/error.hpp"
#include "holo/kiosk/degradation_policy.hpp"

namespace holo::kiosk {
namespace {

DegradationSettings fastSettings() {
  DegradationSettings s;
  s.quality_levels = {"full", "reduced", "low"};
  s.frame_budget_ms = 40;
  s.headroom = 0.7;
  s.smoothing = 1.0;  // no averaging: each frame decides alone, so counts are exact
  s.down_after_frames = 3;
  s.up_after_frames = 5;
  s.cooldown_frames = 2;
  s.recover_after_frames = 4;
  return s;
}

TEST(DegradationPolicy, StepsDownAfterSustainedOverloadOnly) {
  DegradationPolicy p(fastSettings());
  // Two slow frames and a fast one: a spike, not an overload.
  p.update(60, 4, 4);
  p.update(60, 4, 4);
  p.update(20, 4, 4);
  EXPECT_EQ(p.quality(), 0);
  EXPECT_FALSE(p.update(60, 4, 4).quality_changed);
  EXPECT_FALSE(p.update(60, 4, 4).quality_changed);
  const auto d = p.update(60, 4, 4);
  EXPECT_TRUE(d.quality_changed);
  EXPECT_EQ(d.quality, 1);
  EXPECT_EQ(p.qualityName(), "reduced");
}

TEST(DegradationPolicy, StepsThroughEveryLevelAndStopsAtTheLast) {
  DegradationPolicy p(fastSettings());
  int changes = 0;
  for (int i = 0; i < 100; ++i) changes += p.update(500, 4, 4).quality_changed ? 1 : 0;
  EXPECT_EQ(p.quality(), 2);
  EXPECT_EQ(changes, 2);
}

TEST(DegradationPolicy, RecoversWithHeadroomButHoldsInsideTheHysteresisBand) {
  DegradationPolicy p(fastSettings());
  for (int i = 0; i < 20; ++i) p.update(500, 4, 4);
  ASSERT_EQ(p.quality(), 2);
  // 35 ms is under the budget but above headroom (28 ms): hold the level forever.
  for (int i = 0; i < 100; ++i) p.update(35, 4, 4);
  EXPECT_EQ(p.quality(), 2);
  // 20 ms is real headroom: up one level after up_after_frames, then cooldown, then up again.
  int frames_to_first_step = 0;
  while (p.quality() == 2 && frames_to_first_step < 100) {
    p.update(20, 4, 4);
    ++frames_to_first_step;
  }
  EXPECT_EQ(frames_to_first_step, 5);
  for (int i = 0; i < 100; ++i) p.update(20, 4, 4);
  EXPECT_EQ(p.quality(), 0);
}

TEST(DegradationPolicy, CooldownPreventsBackToBackSteps) {
  DegradationPolicy p(fastSettings());
  int frame_of_first = -1, frame_of_second = -1;
  for (int i = 0; i < 30 && frame_of_second < 0; ++i) {
    if (p.update(500, 4, 4).quality_changed) (frame_of_first < 0 ? frame_of_first : frame_of_second) = i;
  }
  // Second step needs the cooldown (2) plus a fresh run of down_after_frames (3).
  EXPECT_EQ(frame_of_first, 2);
  EXPECT_EQ(frame_of_second, frame_of_first + 2 + 3);
}

TEST(DegradationPolicy, BrokenTimingsCountAsOverloadNotAsHeadroom) {
  DegradationPolicy p(fastSettings());
  for (int i = 0; i < 3; ++i) p.update(std::numeric_limits<double>::quiet_NaN(), 4, 4);
  EXPECT_EQ(p.quality(), 1);
  for (int i = 0; i < 20; ++i) p.update(-5.0, 4, 4);
  EXPECT_EQ(p.quality(), 2);
  EXPECT_TRUE(std::isfinite(p.smoothedFrameMs()));
}

TEST(DegradationPolicy, CameraLossDegradesAtOnceAndRecoversWithHysteresis) {
  DegradationPolicy p(fastSettings());
  EXPECT_EQ(p.update(20, 4, 4).mode, RenderMode::Full);
  auto d = p.update(20, 3, 4);
  EXPECT_TRUE(d.mode_changed);
  EXPECT_EQ(d.mode, RenderMode::Partial);
  d = p.update(20, 0, 4);
  EXPECT_EQ(d.mode, RenderMode::IblOnly);
  // A camera flaps back for fewer frames than recover_after_frames: no change.
  for (int i = 0; i < 3; ++i) EXPECT_EQ(p.update(20, 4, 4).mode, RenderMode::IblOnly);
  EXPECT_EQ(p.update(20, 0, 4).mode, RenderMode::IblOnly);
  // Stable again for 4 frames: back to full in one step.
  for (int i = 0; i < 3; ++i) p.update(20, 4, 4);
  d = p.update(20, 4, 4);
  EXPECT_TRUE(d.mode_changed);
  EXPECT_EQ(d.mode, RenderMode::Full);
  EXPECT_STREQ(renderModeName(RenderMode::IblOnly), "ibl-only");
}

TEST(DegradationPolicy, NoCamerasConfiguredMeansIblOnly) {
  DegradationPolicy p(fastSettings());
  EXPECT_EQ(p.update(20, 0, 0).mode, RenderMode::IblOnly);
}

TEST(DegradationPolicy, RejectsSettingsThatCannotWork) {
  auto s = fastSettings();
  s.quality_levels.clear();
  EXPECT_THROW(DegradationPolicy{s}, InputError);
  s = fastSettings();
  s.frame_budget_ms = 0;
  EXPECT_THROW(DegradationPolicy{s}, InputError);
  s = fastSettings();
  s.headroom = 1.0;
  EXPECT_THROW(DegradationPolicy{s}, InputError);
}

}  // namespace
}  // namespace holo::kiosk
