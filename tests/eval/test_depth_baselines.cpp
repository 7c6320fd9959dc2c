// The baseline depth filters (temporal median, TAA) beside ours on the synthetic sequence: ours
// steadier on the static box, the moving disc not deformed, the holes filled.
#include <gtest/gtest.h>

#include <cstdio>
#include <utility>

#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "holo/eval/depth_baselines.hpp"
#include "synthetic_filter_run.hpp"

namespace holo::eval {
namespace {

using depthfilter::DepthFilterInput;
using depthfilter::TemporalDepthFilter;
using test::quickFilterConfig;
using test::rawDepthOnMask;
using test::runOnSyntheticScene;
using test::SyntheticRunMetrics;

TEST(TemporalDepthFilter, StableFilledAndUndeformedAgainstBaselines) {
  const test::SyntheticScene scene;
  const int skip = 12, frames = 30;
  TemporalDepthFilter ours(quickFilterConfig());
  TemporalMedianDepthFilter median(5);
  TaaDepthFilter taa(0.1f);
  const SyntheticRunMetrics m_raw = runOnSyntheticScene(scene, rawDepthOnMask, skip, frames);
  const SyntheticRunMetrics m_ours = runOnSyntheticScene(
      scene, [&](const DepthFilterInput& in) { return ours.apply(in); }, skip, frames);
  const SyntheticRunMetrics m_median = runOnSyntheticScene(
      scene, [&](const DepthFilterInput& in) { return median.apply(in); }, skip, frames);
  const SyntheticRunMetrics m_taa = runOnSyntheticScene(
      scene, [&](const DepthFilterInput& in) { return taa.apply(in); }, skip, frames);
  for (const auto& [name, m] :
       {std::pair{"raw", m_raw}, {"ours", m_ours}, {"median", m_median}, {"taa", m_taa}})
    std::printf("%-6s temporal_mse %.4f cm2  rmse disc %.3f cm  rmse box %.3f cm  fill %.4f\n", name,
                m.temporal_mse_static_cm2, m.rmse_disc_cm, m.rmse_box_cm, m.hole_fill);
  EXPECT_FALSE(ours.learning());
  EXPECT_LT(m_ours.temporal_mse_static_cm2, m_raw.temporal_mse_static_cm2 / 10.0);
  EXPECT_LT(m_ours.temporal_mse_static_cm2, m_median.temporal_mse_static_cm2);
  EXPECT_LE(m_ours.rmse_disc_cm, m_raw.rmse_disc_cm);  // the moving disc is not deformed
  EXPECT_LE(m_ours.rmse_box_cm, m_raw.rmse_box_cm);
  EXPECT_GT(m_ours.hole_fill, 0.995);
  EXPECT_LT(m_raw.hole_fill, 0.98);
}

}  // namespace
}  // namespace holo::eval
