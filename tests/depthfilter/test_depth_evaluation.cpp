#include <gtest/gtest.h>
#include <vector>

#include "holo/depthfilter/depth_evaluation.hpp"
#include "synthetic_rgbd.hpp"

namespace holo::depthfilter {
namespace {

TEST(DepthFilterEvaluation, ScoresEveryMethodOnTheSyntheticSequence) {
  test::SyntheticScene scene;
  test::SyntheticScene empty = scene;
  empty.objects = false;
  DepthEvaluationConfig config;
  config.filter.learning_frames = 10;
  config.filter.levels = 6;  // the 12x10 hole in the box needs l_max >= 5; edges here are simple
  std::vector<DepthFilterEvaluation> streams;
  streams.emplace_back(config);
  for (int t = 0; t < 10; ++t) streams[0].learnBackground(empty.render(t, 50).frame);
  for (int t = 0; t < 30; ++t) {
    const test::SyntheticFrame f = scene.render(t, 51);
    streams[0].addFrame({f.frame, f.true_depth, f.true_mask});
  }
  const DepthMethodMetrics ours = DepthFilterEvaluation::combined(streams, DepthMethod::Ours);
  const DepthMethodMetrics raw = DepthFilterEvaluation::combined(streams, DepthMethod::Raw);
  const DepthMethodMetrics median = DepthFilterEvaluation::combined(streams, DepthMethod::Median);
  const DepthMethodMetrics taa = DepthFilterEvaluation::combined(streams, DepthMethod::Taa);
  for (DepthMethod m : kDepthMethods) {
    const DepthMethodMetrics r = streams[0].metrics(m);
    std::printf(
        "%-6s temporal %.4f cm2 rmse %.3f cm fill %.4f (raw holes %.4f) ghost %.4f %.2f ms (%ld frames)\n",
        depthMethodName(m), r.temporal_mse_cm2, r.depth_rmse_cm, r.hole_fill_ratio, r.raw_holes_filled,
        r.ghost_ratio, r.ms_per_frame, r.scored_frames);
  }
  EXPECT_EQ(ours.scored_frames, 20);
  EXPECT_EQ(raw.scored_frames, 20);
  EXPECT_LT(ours.temporal_mse_cm2, raw.temporal_mse_cm2 / 5.0);
  EXPECT_LT(ours.temporal_mse_cm2, median.temporal_mse_cm2);
  EXPECT_LE(ours.depth_rmse_cm, raw.depth_rmse_cm);
  EXPECT_GT(ours.hole_fill_ratio, 0.99);
  EXPECT_LT(raw.hole_fill_ratio, 0.98);
  EXPECT_EQ(raw.raw_holes_filled, 0.0);  // raw fills none of its own holes, by definition
  EXPECT_GT(ours.raw_holes_filled, 0.8);
  EXPECT_LT(ours.ghost_ratio, 0.02);
  EXPECT_GT(median.depth_rmse_cm, ours.depth_rmse_cm);  // the median smears the moving disc
  EXPECT_GT(taa.scored_frames, 0);
  EXPECT_FALSE(streams[0].lastOutput(DepthMethod::Ours).empty());
}

}  // namespace
}  // namespace holo::depthfilter
