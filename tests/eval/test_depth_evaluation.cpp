#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/coverage_breakdown.hpp"
#include "holo/eval/depth_evaluation.hpp"
#include "synthetic_rgbd.hpp"

namespace holo::eval {
namespace {

// A 4x4 visitor at 2 m filling the frame; the sensor reads it `sensor_error_m` too far.
GroundTruthFrame flatVisitor(float sensor_error_m = 0.01f) {
  GroundTruthFrame truth;
  truth.true_depth = cv::Mat(4, 4, CV_32FC1, cv::Scalar(2.0f));
  truth.true_foreground = cv::Mat(4, 4, CV_8UC1, cv::Scalar(255));
  truth.frame.depth = cv::Mat(4, 4, CV_32FC1, cv::Scalar(2.0f + sensor_error_m));
  truth.frame.colour = cv::Mat(4, 4, CV_8UC3, cv::Scalar(0, 0, 0));
  return truth;
}

TEST(DepthScorer, PixelFlickeringBetweenADepthAndAHoleCostsSomething) {
  DepthScorer flicker, steady;
  for (int t = 0; t < 3; ++t) {
    const GroundTruthFrame truth = flatVisitor(0.01f * float(t % 2));  // the sensor's S is 1 cm^2
    cv::Mat out = truth.true_depth.clone();  // exact: only the flicker can cost anything
    steady.add(out, truth);
    if (t % 2 == 1) out.at<float>(1, 2) = 0.0f;
    flicker.add(out, truth);
  }
  EXPECT_EQ(steady.metrics().temporal_mse_cm2, 0.0);
  // Each of the two frame pairs: one of 16 pixel pairs has a hole and costs S.
  EXPECT_NEAR(flicker.metrics().temporal_mse_cm2, 1.0 / 16.0, 1e-6);
  EXPECT_NEAR(flicker.metrics().hole_pair_ratio, 1.0 / 16.0, 1e-12);
}

TEST(DepthScorer, HolesCountInTheDepthErrorAndCoverageOfEveryTrueVisitorPixel) {
  const GroundTruthFrame truth = flatVisitor();
  DepthScorer scorer;
  cv::Mat out = truth.true_depth.clone();
  out.rowRange(0, 2).setTo(0.0f);  // half of the visitor has no depth, e.g. outside the mask
  scorer.add(out, truth);
  const DepthMethodMetrics m = scorer.metrics();
  EXPECT_NEAR(m.coverage, 0.5, 1e-12);
  EXPECT_NEAR(m.depth_rmse_cm, std::sqrt(0.5), 1e-4);  // 8 holes at the sensor's 1 cm, 8 exact pixels
  EXPECT_TRUE(std::isnan(m.temporal_mse_cm2)) << "one frame has no pair";
}

TEST(DepthScorer, AHoleCostsTheSensorsAverage) {
  DepthScorer scorer;
  for (int t = 0; t < 2; ++t) {
    GroundTruthFrame truth = flatVisitor(0.01f * float(t));  // every reading changes its error by 1 cm
    truth.frame.depth.at<float>(0, 0) = 0.0f;
    cv::Mat out = truth.true_depth.clone();
    out.at<float>(0, 0) = 0.0f;
    scorer.add(out, truth);
  }
  const DepthMethodMetrics m = scorer.metrics();
  EXPECT_NEAR(m.sensor_temporal_mse_cm2, 1.0, 1e-4);
  EXPECT_NEAR(m.sensor_rmse_cm, std::sqrt(0.5), 1e-4);              // readings 0 and 1 cm off
  EXPECT_NEAR(m.temporal_mse_cm2, 1.0 / 16.0, 1e-4);                // 15 exact pairs and one at 1 cm^2
  EXPECT_NEAR(m.depth_rmse_cm, std::sqrt(2.0 * 0.5 / 32.0), 1e-4);  // 2 of 32 pixels at 0.5 cm^2
}

TEST(DepthScorer, NothingToScoreIsNotPerfect) {
  GroundTruthFrame nobody = flatVisitor();
  nobody.true_foreground.setTo(0);
  DepthScorer scorer;
  for (int t = 0; t < 3; ++t) scorer.add(cv::Mat::zeros(4, 4, CV_32FC1), nobody);
  const DepthMethodMetrics m = scorer.metrics();
  EXPECT_TRUE(std::isnan(m.temporal_mse_cm2));
  EXPECT_TRUE(std::isnan(m.depth_rmse_cm));
  EXPECT_TRUE(std::isnan(m.coverage));
  EXPECT_TRUE(std::isnan(m.ghost_ratio));
  EXPECT_EQ(m.scored_frames, 3);
  // NaN fails every bar, even against baselines with nothing to score either.
  const DepthBarVerdicts v = checkDepthBars(m, m, m, m);
  EXPECT_FALSE(v.below_median || v.below_taa || v.rmse_below_raw || v.coverage || v.ghosts);
}

// A noisy sensor watching a visitor walk away, and the adversary that drops its readings wherever
// they moved by more than 1 cm: counting only the pixels with a depth in both frames it would look
// nearly 6x steadier than the sensor; with holes counted it cannot look even twice as steady. The
// sensor's own holes cost its average, so its RMSE over every visitor pixel is that of its readings.
TEST(DepthScorer, LeavingHolesWhereTheDepthMovedBuysLittle) {
  cv::RNG rng(7);
  HoleLeavingAdversary adversary(0.01f);
  DepthScorer sensor, dropped;
  for (int t = 0; t < 20; ++t) {
    GroundTruthFrame truth;
    truth.true_depth = cv::Mat(16, 16, CV_32FC1, cv::Scalar(2.0f + 0.01f * float(t)));
    truth.true_foreground = cv::Mat(16, 16, CV_8UC1, cv::Scalar(255));
    cv::Mat noise(16, 16, CV_32FC1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.02);
    truth.frame.depth = truth.true_depth + noise;
    truth.frame.depth.setTo(0.0f, noise > 0.035f);  // the sensor's own dropouts
    truth.frame.colour = cv::Mat(16, 16, CV_8UC3, cv::Scalar(0, 0, 0));
    sensor.add(truth.frame.depth, truth);
    dropped.add(adversary.apply(truth.frame.depth), truth);
  }
  const DepthMethodMetrics s = sensor.metrics(), d = dropped.metrics();
  std::printf("sensor temporal %.3f cm2 rmse %.3f cm; adversary temporal %.3f cm2 coverage %.3f\n",
              s.temporal_mse_cm2, s.depth_rmse_cm, d.temporal_mse_cm2, d.coverage);
  EXPECT_GT(s.temporal_mse_cm2, 5.0);  // 2 cm noise: about 2 * 4 cm^2
  EXPECT_GT(d.temporal_mse_cm2, 0.5 * s.temporal_mse_cm2);
  EXPECT_LT(d.coverage, 0.5);
  EXPECT_NEAR(s.depth_rmse_cm, s.sensor_rmse_cm, 1e-9);
  EXPECT_LT(s.coverage, 0.98);
}

// Six true visitor pixels, one of each class: covered, outside the mask within the background's
// margin, in front of it, where no background depth is learned, without a reading, and a hole
// the filter left at the mask's edge; a seventh pixel is no visitor and is not counted.
TEST(CoverageBreakdown, ClassesEveryTrueVisitorPixelOnce) {
  const cv::Mat truth_fg = (cv::Mat_<std::uint8_t>(1, 7) << 255, 255, 255, 255, 255, 255, 0);
  const cv::Mat truth = (cv::Mat_<float>(1, 7) << 2, 2, 2, 2, 2, 2, 0);
  const cv::Mat sensor = (cv::Mat_<float>(1, 7) << 2, 2.99f, 2, 2, 0, 0, 3);
  const cv::Mat background = (cv::Mat_<float>(1, 7) << 3, 3, 3, 0, 3, 3, 3);
  const cv::Mat mask = (cv::Mat_<std::uint8_t>(1, 7) << 255, 0, 0, 0, 0, 255, 0);
  const cv::Mat output = (cv::Mat_<float>(1, 7) << 2, 0, 0, 0, 0, 0, 0);
  const cv::Mat reasons =
      (cv::Mat_<std::uint8_t>(1, 7) << 0, 0, 0, 0, 0, std::uint8_t(depthfilter::HoleReason::MaskEdge), 0);
  CoverageBreakdown b{depthfilter::ForegroundMaskConfig{}};
  b.add({truth_fg, truth, sensor, background, mask, output, reasons});
  EXPECT_EQ(b.visitorPixels(), 6);
  const double sixth = 1.0 / 6.0;
  EXPECT_DOUBLE_EQ(b.covered(), sixth);
  EXPECT_DOUBLE_EQ(b.outsideWithinMargin(), sixth);
  EXPECT_DOUBLE_EQ(b.outsideInFront(), sixth);
  EXPECT_DOUBLE_EQ(b.outsideUnknownBackground(), sixth);
  EXPECT_DOUBLE_EQ(b.outsideNoDepth(), sixth);
  EXPECT_DOUBLE_EQ(b.hole(depthfilter::HoleReason::MaskEdge, false), sixth);
  EXPECT_DOUBLE_EQ(b.holes(), sixth);
  EXPECT_THROW(b.add({truth_fg, truth, sensor, background, mask, output, cv::Mat()}), Error);
}

TEST(HoleLeavingAdversary, DropsEveryPixelWhoseDepthChangedByMoreThanK) {
  HoleLeavingAdversary adversary(0.01f);
  cv::Mat depth(1, 4, CV_32FC1, cv::Scalar(2.0f));
  depth.at<float>(0, 3) = 0.0f;
  EXPECT_EQ(cv::countNonZero(adversary.apply(depth)), 3);  // nothing to compare with yet
  cv::Mat next = depth.clone();
  next.at<float>(0, 0) = 2.005f;  // kept
  next.at<float>(0, 1) = 2.02f;   // dropped
  next.at<float>(0, 3) = 1.5f;    // had no depth: kept
  const cv::Mat out = adversary.apply(next);
  EXPECT_EQ(out.at<float>(0, 0), 2.005f);
  EXPECT_EQ(out.at<float>(0, 1), 0.0f);
  EXPECT_EQ(out.at<float>(0, 2), 2.0f);
  EXPECT_EQ(out.at<float>(0, 3), 1.5f);
}

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
        "%-9s temporal %.4f cm2 rmse %.3f cm coverage %.4f hole pairs %.4f (raw holes %.4f) ghost %.4f %.2f "
        "ms "
        "(%ld frames)\n",
        depthMethodName(m), r.temporal_mse_cm2, r.depth_rmse_cm, r.coverage, r.hole_pair_ratio,
        r.raw_holes_filled, r.ghost_ratio, r.ms_per_frame, r.scored_frames);
  }
  EXPECT_EQ(ours.scored_frames, 20);
  EXPECT_EQ(raw.scored_frames, 20);
  EXPECT_LT(ours.temporal_mse_cm2, raw.temporal_mse_cm2 / 5.0);
  EXPECT_LT(ours.temporal_mse_cm2, median.temporal_mse_cm2);
  EXPECT_LE(ours.depth_rmse_cm, raw.depth_rmse_cm);
  EXPECT_GT(ours.coverage, 0.99);
  EXPECT_LT(raw.coverage, 0.98);
  EXPECT_EQ(raw.raw_holes_filled, 0.0);  // raw fills none of its own holes, by definition
  EXPECT_GT(ours.raw_holes_filled, 0.8);
  EXPECT_LT(ours.ghost_ratio, 0.02);
  EXPECT_GT(median.depth_rmse_cm, ours.depth_rmse_cm);  // the median smears the moving disc
  EXPECT_GT(taa.scored_frames, 0);
  EXPECT_FALSE(streams[0].lastOutput(DepthMethod::Ours).empty());
}

}  // namespace
}  // namespace holo::eval
