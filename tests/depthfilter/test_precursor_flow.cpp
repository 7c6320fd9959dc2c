#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "holo/depthfilter/precursor_flow.hpp"
#include "synthetic_rgbd.hpp"

namespace holo::depthfilter {
namespace {

// Mean end-point error of the precursor flow on the moving disc's interior (true backward flow:
// -disc_speed_px in x) and on the static background.
struct FlowError {
  double disc_px = 0.0;
  double background_px = 0.0;
};

FlowError flowError(int preset, int downscale = 1, int width = 320, int height = 180) {
  test::SyntheticScene scene;
  if (width != scene.width) {  // the benchmark's 640x360 version of the scene
    scene.width = width;
    scene.height = height;
    scene.focal = 500.0f;
    scene.box = {80, 100, 120, 160};
    scene.disc_radius_px = 56.0f;
  }
  PrecursorFlow flow({preset, downscale});
  const test::SyntheticFrame previous = scene.render(4, 3);
  const test::SyntheticFrame current = scene.render(5, 3);
  const cv::Mat lambda = flow.compute(current.frame.colour, previous.frame.colour);
  cv::Mat disc, background;
  cv::erode(current.disc_mask, disc, cv::Mat::ones(7, 7, CV_8UC1));
  cv::dilate(current.true_mask | previous.true_mask, background, cv::Mat::ones(9, 9, CV_8UC1));
  background = background == 0;
  double disc_sum = 0, bg_sum = 0;
  long disc_n = 0, bg_n = 0;
  for (int y = 0; y < lambda.rows; ++y)
    for (int x = 0; x < lambda.cols; ++x) {
      const cv::Vec2f f = lambda.at<cv::Vec2f>(y, x);
      if (disc.at<std::uint8_t>(y, x)) {
        disc_sum += std::hypot(f[0] + scene.disc_speed_px, f[1]);
        ++disc_n;
      } else if (background.at<std::uint8_t>(y, x)) {
        bg_sum += std::hypot(f[0], f[1]);
        ++bg_n;
      }
    }
  return {disc_sum / double(disc_n), bg_sum / double(bg_n)};
}

// The forward-backward check on the moving disc: the background the disc uncovers was hidden in the
// previous frame, so its precursor (the disc's pixel there) does not map back to it and is
// rejected (NaN); the disc's interior and the background far from it keep theirs. At the default
// 2 px DIS's smooth half-size flows catch about a third of the uncovered strip (measured 0.31;
// 1 px: 0.70, but 10% of the disc and 5% of the background rejected too).
TEST(PrecursorFlow, RoundTripCheckRejectsPrecursorsHiddenInThePreviousFrame) {
  test::SyntheticScene scene;  // four frames apart: the disc moves 8 px
  const test::SyntheticFrame previous = scene.render(2, 3);
  const test::SyntheticFrame current = scene.render(6, 3);
  PrecursorFlowConfig config;
  config.round_trip_check = true;
  PrecursorFlow checked(config), unchecked;
  const cv::Mat with = checked.compute(current.frame.colour, previous.frame.colour);
  const cv::Mat without = unchecked.compute(current.frame.colour, previous.frame.colour);
  cv::Mat uncovered = previous.disc_mask & ~current.disc_mask, disc, background;
  cv::erode(uncovered, uncovered, cv::Mat::ones(3, 3, CV_8UC1));
  cv::erode(current.disc_mask, disc, cv::Mat::ones(7, 7, CV_8UC1));
  cv::dilate(current.true_mask | previous.true_mask, background, cv::Mat::ones(9, 9, CV_8UC1));
  background = background == 0;
  const auto rejected_share = [](const cv::Mat& flow, const cv::Mat& where) {
    long rejected = 0, n = 0;
    for (int y = 0; y < flow.rows; ++y)
      for (int x = 0; x < flow.cols; ++x) {
        if (!where.at<std::uint8_t>(y, x)) continue;
        ++n;
        rejected += !std::isfinite(flow.at<cv::Vec2f>(y, x)[0]);
      }
    return n > 0 ? double(rejected) / double(n) : -1.0;
  };
  const double uncovered_share = rejected_share(with, uncovered);
  std::printf("rejected: uncovered %.3f disc %.3f background %.3f\n", uncovered_share,
              rejected_share(with, disc), rejected_share(with, background));
  EXPECT_GT(uncovered_share, 0.2);
  EXPECT_LT(rejected_share(with, disc), 0.05);
  EXPECT_LT(rejected_share(with, background), 0.02);
  EXPECT_EQ(rejected_share(without, uncovered), 0.0);  // off: every precursor kept
}

TEST(PrecursorFlow, DefaultPresetFindsPrecursorsWithSubpixelError) {
  const FlowError e = flowError(PrecursorFlowConfig{}.preset);
  EXPECT_LT(e.disc_px, 0.5);
  EXPECT_LT(e.background_px, 0.2);
}

TEST(PrecursorFlow, PresetsCompared) {
  // The measurement behind the default preset (docs/depthfilter.md); timings are in
  // bench_depthfilter. Every preset must at least track the disc.
  for (int preset : {cv::DISOpticalFlow::PRESET_ULTRAFAST, cv::DISOpticalFlow::PRESET_FAST,
                     cv::DISOpticalFlow::PRESET_MEDIUM}) {
    const FlowError e = flowError(preset);
    std::printf("DIS preset %d: end-point error disc %.3f px, background %.3f px\n", preset, e.disc_px,
                e.background_px);
    EXPECT_LT(e.disc_px, 1.0);
  }
}

TEST(PrecursorFlow, FirstFrameAndConfidence) {
  const test::SyntheticScene scene;
  PrecursorFlow flow;
  const cv::Mat lambda = flow.compute(scene.render(0, 1).frame.colour, cv::Mat());
  EXPECT_EQ(cv::countNonZero(lambda.reshape(1)), 0);  // no previous frame: zero flow
  EXPECT_FLOAT_EQ(precursorConfidence({10, 20, 30}, {10, 20, 30}), 0.0f);
  EXPECT_FLOAT_EQ(precursorConfidence({0, 0, 0}, {255, 255, 255}), std::sqrt(3.0f) * 255.0f);
  EXPECT_FLOAT_EQ(precursorConfidence({3, 0, 0}, {0, 4, 0}), 5.0f);
}

TEST(PrecursorFlow, HalfSizeFlowAt640x360) {
  // The speed option (docs/depthfilter.md, "Speed"): DIS on frames downscaled by 2.
  for (int downscale : {1, 2}) {
    const FlowError e = flowError(PrecursorFlowConfig{}.preset, downscale, 640, 360);
    std::printf("640x360, downscale %d: end-point error disc %.3f px, background %.3f px\n", downscale,
                e.disc_px, e.background_px);
    EXPECT_LT(e.disc_px, 0.5);
    EXPECT_LT(e.background_px, 0.2);
  }
}

// next() keeps the previous frame's flow image instead of making it again from its colour: the
// same flow as compute() with both frames, to the bit (it moves), and none on a first frame, after
// reset() or a size change.
TEST(PrecursorFlow, NextGivesTheFlowComputeGivesFromTheFrameBefore) {
  test::SyntheticScene scene;
  std::vector<cv::Mat> colours;
  for (int t = 0; t < 4; ++t) colours.push_back(scene.render(t, 3).frame.colour);
  PrecursorFlow kept, fresh;
  EXPECT_EQ(cv::countNonZero(kept.next(colours[0]).reshape(1)), 0);
  double moved = 0.0;
  for (int t = 1; t < 4; ++t) {
    const cv::Mat a = kept.next(colours[std::size_t(t)]);
    const cv::Mat b = fresh.compute(colours[std::size_t(t)], colours[std::size_t(t) - 1]);
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0) << "frame " << t;
    moved = std::max(moved, cv::norm(a, cv::NORM_INF));
  }
  EXPECT_GT(moved, 1.0);
  kept.reset();
  EXPECT_EQ(cv::countNonZero(kept.next(colours[1]).reshape(1)), 0);
  cv::Mat smaller;
  cv::resize(colours[2], smaller, cv::Size(colours[2].cols / 2, colours[2].rows / 2));
  EXPECT_EQ(cv::countNonZero(kept.next(smaller).reshape(1)), 0);
}

// next() with a region brings only that region to full size: bit for bit the whole frame's flow
// inside it (blocks touching the frame's edges, odd and even corners, a single pixel, with the
// round-trip check), 0 outside it, and all 0 for an empty region.
TEST(PrecursorFlow, NextInsideARegionEqualsTheWholeFrameThereAndZeroElsewhere) {
  test::SyntheticScene scene;
  std::vector<cv::Mat> colours;
  for (int t = 0; t < 3; ++t) colours.push_back(scene.render(t, 3).frame.colour);
  const std::vector<cv::Rect> regions{{0, 0, 320, 180},  {37, 21, 101, 77}, {0, 50, 91, 130},
                                      {200, 0, 120, 61}, {151, 88, 1, 1},   {-20, 170, 400, 40}};
  for (const bool check : {false, true}) {
    for (const cv::Rect& region : regions) {
      PrecursorFlowConfig config;
      config.round_trip_check = check;
      PrecursorFlow whole(config), part(config);
      for (std::size_t t = 0; t < colours.size(); ++t) {
        const cv::Mat full = whole.next(colours[t]);
        const cv::Mat inside = part.next(colours[t], region);
        const cv::Rect r = region & cv::Rect(0, 0, full.cols, full.rows);
        cv::Mat outside_mask(full.size(), CV_8UC1, cv::Scalar(255));
        outside_mask(r).setTo(0);
        // NaN (rejected by the check) compares unequal to itself: compare the bits.
        EXPECT_EQ(std::memcmp(full(r).clone().data, inside(r).clone().data, r.area() * sizeof(cv::Vec2f)), 0)
            << region << " frame " << t << " check " << check;
        cv::Mat outside;
        inside.copyTo(outside, outside_mask);
        EXPECT_EQ(cv::countNonZero(outside.reshape(1)), 0) << region;
        if (t > 0 && r.area() > 1) {
          EXPECT_GT(cv::countNonZero(full(r).reshape(1) != 0), 0) << region;  // a flow to compare
        }
      }
    }
  }
  PrecursorFlow flow;
  flow.next(colours[0]);
  EXPECT_EQ(cv::countNonZero(flow.next(colours[1], cv::Rect()).reshape(1)), 0);
}

}  // namespace
}  // namespace holo::depthfilter
