// The displayed reflection flicker (reflection_flicker.hpp) on hand-made displays: the truth
// scores 0, a change beyond the truth's counts, and a method that drops the visitors' reflection
// does not win; then on the simulated museum at CI size (four cameras, 320x180, 8 scored frames,
// the live renderer on 160-pixel face views to keep the test cheap): ours against raw, the median
// and TAA fed through the same renderer, and the adversaries. The full evaluation is `holopyramid eval depth
// --scene S --frames 60` (docs/depthfilter.md).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "holo/core/error.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "holo/eval/reflection_flicker.hpp"
#include "holo/eval/simulated_depth_evaluation.hpp"

namespace holo::eval {
namespace {

constexpr int kSize = 48;
const cv::Vec3b kRelic(90, 90, 90);

// One view: the relic's grey, and a visitor's reflection (a square of `level` whose left edge is
// at `x0`) where `shown`. Its weight is 1 on the square.
DisplayedFrame reflection(int x0, int level, bool shown) {
  DisplayedFrame f;
  f.display.push_back(cv::Mat(kSize, kSize, CV_8UC3, cv::Scalar(kRelic[0], kRelic[1], kRelic[2])));
  f.weight.push_back(cv::Mat::zeros(kSize, kSize, CV_32FC1));
  if (shown) {
    const cv::Rect square(x0, 12, 16, 16);
    f.display[0](square).setTo(cv::Scalar(level, level, level));
    f.weight[0](square).setTo(1.0f);
  }
  return f;
}

// Adds uniform noise of +-amplitude levels to the display where the weight is positive.
DisplayedFrame noisy(const DisplayedFrame& shown, int amplitude, std::mt19937& rng) {
  DisplayedFrame f{{shown.display[0].clone()}, {shown.weight[0].clone()}};
  std::uniform_int_distribution<int> noise(-amplitude, amplitude);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      if (f.weight[0].at<float>(y, x) > 0.0f)
        for (int c = 0; c < 3; ++c) {
          uchar& v = f.display[0].at<cv::Vec3b>(y, x)[c];
          v = cv::saturate_cast<uchar>(int(v) + noise(rng));
        }
  return f;
}

TEST(ReflectionFlicker, TheTruthScoresNothingAndAChangeBeyondItsOwnCounts) {
  ReflectionFlickerScorer same, shaken;
  std::mt19937 rng(7);
  for (int t = 0; t < 6; ++t) {
    const DisplayedFrame truth = reflection(10 + t, 200, true);
    same.add(truth, truth);
    shaken.add(noisy(truth, 8, rng), truth);
  }
  EXPECT_EQ(same.metrics().flicker, 0.0);
  EXPECT_EQ(same.metrics().scored_pairs, 5);
  EXPECT_GT(same.metrics().displayed_change, 0.0);  // the visitor moved
  // Uniform noise of +-8 levels in two frames: E[(n1 - n0)^2] = 2 * 8 * 9 / 3 = 48 levels^2.
  EXPECT_NEAR(shaken.metrics().flicker, 48.0, 12.0);
  EXPECT_EQ(shaken.metrics().missing_share, 0.0);
}

TEST(ReflectionFlicker, AMethodThatDropsTheVisitorsReflectionDoesNotWin) {
  ReflectionFlickerScorer shows, drops;
  std::mt19937 rng(11);
  for (int t = 0; t < 8; ++t) {
    // A visitor standing nearly still: the truth's own change is small.
    const DisplayedFrame truth = reflection(16, 200 + (t % 2), true);
    shows.add(noisy(truth, 6, rng), truth);
    drops.add(reflection(16, 0, false), truth);
  }
  const ReflectionFlickerMetrics s = shows.metrics(), d = drops.metrics();
  std::printf("shows: flicker %.2f (temporal %.2f); drops: flicker %.2f (temporal %.2f, missing %.2f)\n",
              s.flicker, s.temporal, d.flicker, d.temporal, d.missing);
  // Its display never changes: on the change alone it would beat the method that shows the
  // visitor with a little noise.
  EXPECT_LT(d.temporal, s.temporal);
  EXPECT_EQ(d.missing_share, 1.0);
  // Counted as the reflection switched off, it loses by far.
  EXPECT_GT(d.flicker, 10.0 * s.flicker);
}

TEST(ReflectionFlicker, RefusesViewsThatDoNotMatch) {
  ReflectionFlickerScorer scorer;
  DisplayedFrame one = reflection(10, 200, true), two = one;
  two.display.push_back(one.display[0]);
  EXPECT_THROW(scorer.add(two, one), Error);
  DisplayedFrame small = one;
  small.weight[0] = cv::Mat::zeros(8, 8, CV_32FC1);
  EXPECT_THROW(scorer.add(small, one), Error);
}

// The museum at CI size through every method and the live renderer (the same run for every
// check below).
const SimulatedDepthEvaluation& museumRun() {
  static const SimulatedDepthEvaluation run = [] {
    SimulatedDepthOptions o;
    o.scene = "museum";
    o.width = 320;
    o.height = 180;
    o.learning_frames = 8;
    o.frames = 8;
    o.view_size = 160;
    o.compared_levels = {};
    return evaluateSimulatedDepth(o);
  }();
  return run;
}

ReflectionFlickerMetrics row(const std::string& name) {
  for (const auto& [n, m] : museumRun().flicker_rows)
    if (n == name) return m;
  ADD_FAILURE() << "no flicker row " << name;
  return {};
}

TEST(SimulatedReflectionFlicker, OursFlickersLessThanRawMedianAndTaaAndTheAdversariesFail) {
  for (const auto& [name, m] : museumRun().flicker_rows)
    std::printf(
        "%-24s flicker %8.2f (temporal %7.2f missing %7.2f) missing share %.3f change %7.2f levels2\n",
        name.c_str(), m.flicker, m.temporal, m.missing, m.missing_share, m.displayed_change);
  const ReflectionFlickerMetrics ours = row("ours"), raw = row("raw"), median = row("median"),
                                 taa = row("taa");
  EXPECT_GE(ours.scored_pairs, 7);
  EXPECT_LT(ours.flicker, raw.flicker);
  EXPECT_LT(ours.flicker, median.flicker);
  EXPECT_TRUE(checkFlickerBars(ours, raw, taa).below_taa);
  // The project's bar (3x below raw) is not met here (docs/depthfilter.md has the figures); the
  // adversaries must fail it and lose to ours.
  for (const char* adversary : {"nobody", "adversary"}) {
    EXPECT_FALSE(checkFlickerBars(row(adversary), raw, taa).all()) << adversary;
    EXPECT_GT(row(adversary).flicker, ours.flicker) << adversary;
  }
  EXPECT_EQ(row("nobody").missing_share, 1.0);
  // The truth scores nothing and changes as the visitors move; a perfect depth on the shared mask
  // is the floor the mask leaves to any depth filter.
  EXPECT_EQ(row("truth").flicker, 0.0);
  EXPECT_GT(row("truth").displayed_change, 0.0);
  EXPECT_LT(row("true depth on the mask").flicker, row("true depth on ours' pixels").flicker);
  EXPECT_LT(row("true depth on ours' pixels").flicker, ours.flicker);
}

}  // namespace
}  // namespace holo::eval
