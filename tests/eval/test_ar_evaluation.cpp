// The AR composite on the simulated museum against the path-traced truth (eval/ar_evaluation.hpp)
// at CI size (96x54, truth 256 spp, 16 spp, the two-pass renderer given at least delta path
// tracing's rays: deterministic); HOLO_FULL_EVAL=1 runs the `eval ar` defaults (320x180, truth
// 512 spp) with the same checks.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/ar_evaluation.hpp"

namespace holo::eval {
namespace {

bool fullEvaluation() {
  const char* full = std::getenv("HOLO_FULL_EVAL");
  return full != nullptr && std::string(full) == "1";
}

ArEvaluationOptions options() {
  ArEvaluationOptions o;
  o.equal_time = false;
  if (fullEvaluation()) {
    o.truth_spp = 512;
    return o;
  }
  o.width = 96;
  o.height = 54;
  o.truth_spp = 256;
  o.method_spp = 16;
  return o;
}

// One evaluation for both tests.
const ArEvaluation& evaluation() {
  static const ArEvaluation e = evaluateArComposite(options());
  return e;
}

TEST(ArEvaluation, DeltaPathTracingBeatsTwoPassWhereTheRelicChangesTheRoom) {
  const ArEvaluation& e = evaluation();
  ASSERT_GT(e.relic_pixels, 100) << "the check camera sees the relic";
  ASSERT_GT(e.shadow_pixels, 100) << "and what it changes on the real surfaces";
  EXPECT_GE(e.two_pass.rays, e.delta.rays);
  // Over the real pixels the relic changes, where the two differ (the relic's own pixels are the
  // same path tracing in both).
  EXPECT_GE(e.two_pass.rmse.shadow, kArDeltaOverTwoPass * e.delta.rmse.shadow)
      << "two-pass " << e.two_pass.rmse.shadow << ", delta " << e.delta.rmse.shadow;
  EXPECT_LT(e.delta.rmse.region, e.two_pass.rmse.region);
  EXPECT_LT(e.delta.rmse.image, e.two_pass.rmse.image);
}

TEST(ArEvaluation, TheFilteredCompositeBeatsOneWithoutTheShadowAndTheUnfilteredOne) {
  const ArEvaluation& e = evaluation();
  EXPECT_LT(e.filtered.rmse.shadow, 0.85 * e.delta.rmse.shadow)
      << "filtered " << e.filtered.rmse.shadow << ", unfiltered " << e.delta.rmse.shadow;
  EXPECT_LT(e.filtered.rmse.shadow, 0.8 * e.no_shadow.shadow)
      << "filtered " << e.filtered.rmse.shadow << ", without shadow " << e.no_shadow.shadow;
  EXPECT_LT(e.filtered.rmse.region, e.no_shadow.region);
}

TEST(ArEvaluation, TheEstimatedAlbedoBeatsAUniformGrey) {
  ArEvaluationOptions grey = options();
  grey.estimate_albedo = false;
  const ArEvaluation without = evaluateArComposite(grey);
  const ArEvaluation& with = evaluation();
  EXPECT_LT(with.filtered.rmse.shadow, 0.8 * without.filtered.rmse.shadow)
      << "estimated " << with.filtered.rmse.shadow << ", grey " << without.filtered.rmse.shadow;
}

// The glass vase: the composite refracts the room and the panorama through it, closer to the
// truth than the same composite with the glass read as opaque, and different from it.
TEST(ArEvaluation, GlassRelicsAreTransmissiveAndCloserToTheTruthThanOpaque) {
  ArEvaluationOptions glass = options();
  glass.relic = "glass-vase";
  if (!fullEvaluation()) glass.truth_spp = 128;
  const ArEvaluation e = evaluateArComposite(glass);
  ASSERT_GT(e.relic_pixels, 100);
  ASSERT_TRUE(e.glass_opaque.has_value()) << "the vase's glass is transmissive";
  EXPECT_LT(e.filtered.rmse.region, 0.75 * e.glass_opaque->region)
      << "glass " << e.filtered.rmse.region << ", opaque " << e.glass_opaque->region;
  EXPECT_GT(cv::norm(e.filtered_composite, e.glass_opaque_composite, cv::NORM_L1), 0.0);
  EXPECT_FALSE(evaluation().glass_opaque.has_value()) << "an opaque relic has nothing to compare";
}

}  // namespace
}  // namespace holo::eval
