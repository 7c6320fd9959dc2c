// The depth filter on the simulated museum (sim module): masks against the true foreground and
// every method's Table 2 metrics against the true depth.
#include <gtest/gtest.h>

#include "holo/depthfilter/depth_evaluation.hpp"
#include "holo/sim/museum.hpp"

namespace holo::depthfilter {
namespace {

struct MaskScore {
  long tp = 0, predicted = 0, actual = 0;
  double precision() const { return predicted > 0 ? double(tp) / double(predicted) : 1.0; }
  double recall() const { return actual > 0 ? double(tp) / double(actual) : 1.0; }
};

TEST(SimulatedMuseum, MaskAndFilterAgainstTheTruth) {
  sim::SceneDescription description = sim::loadScene("museum");
  description.camera.width = 320;
  description.camera.height = 180;
  const sim::Museum museum(description);
  // The camera that sees the most visitor pixels at the start.
  int camera = 0;
  long best = -1;
  for (int c = 0; c < museum.cameraCount(); ++c) {
    const long n = cv::countNonZero(museum.renderCamera(c, 0).foreground);
    if (n > best) best = n, camera = c;
  }
  ASSERT_GT(best, 320 * 180 / 100) << "no visitor in view";

  DepthEvaluationConfig config;
  config.filter.learning_frames = 10;
  DepthFilterEvaluation evaluation(config);
  for (int t = 0; t < 8; ++t) evaluation.learnBackground(museum.renderCamera(camera, t, false).frame);
  MaskScore mask;
  const int frames = 40;
  for (int t = 0; t < frames; ++t) {
    const sim::SimulatedFrame f = museum.renderCamera(camera, t);
    evaluation.addFrame({f.frame, f.true_depth, f.foreground});
    const cv::Mat& m = evaluation.lastMask();
    mask.tp += cv::countNonZero(m & f.foreground);
    mask.predicted += cv::countNonZero(m);
    mask.actual += cv::countNonZero(f.foreground);
  }
  std::printf("camera %d mask precision %.4f recall %.4f\n", camera, mask.precision(), mask.recall());
  for (DepthMethod m : kDepthMethods) {
    const DepthMethodMetrics r = evaluation.metrics(m);
    std::printf("%-6s temporal %.4f cm2 rmse %.3f cm fill %.4f ghost %.4f %.2f ms\n", depthMethodName(m),
                r.temporal_mse_cm2, r.depth_rmse_cm, r.hole_fill_ratio, r.ghost_ratio, r.ms_per_frame);
  }
  const DepthMethodMetrics ours = evaluation.metrics(DepthMethod::Ours);
  const DepthMethodMetrics raw = evaluation.metrics(DepthMethod::Raw);
  const DepthMethodMetrics median = evaluation.metrics(DepthMethod::Median);
  EXPECT_GT(mask.precision(), 0.95);
  EXPECT_GT(mask.recall(), 0.95);
  EXPECT_EQ(ours.scored_frames, frames - 10);
  EXPECT_GE(ours.hole_fill_ratio, 0.95);
  EXPECT_GT(ours.hole_fill_ratio, raw.hole_fill_ratio);
  EXPECT_LT(ours.ghost_ratio, 0.03);
  // Against the temporal median, which smears walking visitors into trails.
  EXPECT_LT(ours.temporal_mse_cm2, median.temporal_mse_cm2);
  EXPECT_LT(ours.depth_rmse_cm, median.depth_rmse_cm);
  // Not asserted because it does not hold yet (docs/depthfilter.md, "Simulated museum"): ours
  // beating raw on temporal MSE' and depth RMSE. Filled holes sit mostly on depth edges, where
  // 15-20% of them take the other surface's depth, and both metrics count every output pixel.
}

}  // namespace
}  // namespace holo::depthfilter
