#include <gtest/gtest.h>
#include <limits>

#include "holo/core/error.hpp"

#include "holo/depthfilter/foreground_mask.hpp"
#include "synthetic_rgbd.hpp"

namespace holo::depthfilter {
namespace {

struct Score {
  double precision = 0.0;
  double recall = 0.0;
};

Score score(const cv::Mat& mask, const cv::Mat& truth) {
  const double tp = cv::countNonZero(mask & truth);
  const double predicted = cv::countNonZero(mask);
  const double actual = cv::countNonZero(truth);
  return {predicted > 0 ? tp / predicted : 1.0, actual > 0 ? tp / actual : 1.0};
}

ForegroundMasker learnedMasker(const test::SyntheticScene& scene, ForegroundMaskConfig config = {}) {
  ForegroundMasker masker(std::move(config));
  test::SyntheticScene empty = scene;
  empty.objects = false;
  for (int t = 0; t < 20; ++t) masker.learnBackground(empty.render(t, 1).frame);
  return masker;
}

TEST(ForegroundMask, PrecisionAndRecallOnMovingAndStaticObjects) {
  test::SyntheticScene scene;
  ForegroundMasker masker = learnedMasker(scene);
  Score total{0, 0};
  const int frames = 15;
  for (int t = 0; t < frames; ++t) {
    const test::SyntheticFrame f = scene.render(t, 2);
    const Score s = score(masker.apply(f.frame), f.true_mask);
    total.precision += s.precision / frames;
    total.recall += s.recall / frames;
  }
  EXPECT_GT(total.precision, 0.97);
  EXPECT_GT(total.recall, 0.97);
}

TEST(ForegroundMask, ObjectWithBackgroundColourIsFoundByDepth) {
  test::SyntheticScene scene;
  scene.box_matches_background = true;
  ForegroundMasker masker = learnedMasker(scene);
  const test::SyntheticFrame f = scene.render(0, 3);
  const cv::Mat mask = masker.apply(f.frame);
  EXPECT_GT(score(mask, f.box_mask).recall, 0.95);
}

TEST(ForegroundMask, ShadowsAndBrightnessChangesAreBackground) {
  test::SyntheticScene scene;
  scene.objects = false;
  ForegroundMasker masker = learnedMasker(scene);
  // A shadow: a darkened region of the background at the background's depth.
  test::SyntheticFrame shadow = scene.render(30, 4);
  cv::Mat region = shadow.frame.colour(cv::Rect(150, 40, 80, 80));
  region.convertTo(region, -1, 0.55);
  EXPECT_LT(cv::countNonZero(masker.apply(shadow.frame)), 0.002 * scene.width * scene.height);
  // A sudden global brightness change.
  scene.brightness_offset = 40.0f;
  EXPECT_LT(cv::countNonZero(masker.apply(scene.render(31, 4).frame)), 0.002 * scene.width * scene.height);
}

TEST(ForegroundMask, VisitorStandingStillStaysForeground) {
  test::SyntheticScene scene;
  scene.disc_speed_px = 0.0f;
  ForegroundMasker masker = learnedMasker(scene);
  cv::Mat mask;
  test::SyntheticFrame f;
  for (int t = 0; t < 300; t += 1) {  // 10 s at 30 fps
    f = scene.render(t, 5);
    mask = masker.apply(f.frame);
  }
  const Score s = score(mask, f.true_mask);
  EXPECT_GT(s.recall, 0.97);
  EXPECT_GT(s.precision, 0.97);
}

TEST(ForegroundMask, StaticForegroundNeverBecomesBackground) {
  test::SyntheticScene scene;
  scene.objects = false;
  ForegroundMaskConfig config;
  config.static_foreground = cv::Mat::zeros(scene.height, scene.width, CV_8UC1);
  config.static_foreground(cv::Rect(0, scene.height - 20, scene.width, 20)).setTo(255);
  ForegroundMasker masker = learnedMasker(scene, config);
  cv::Mat mask;
  for (int t = 0; t < 50; ++t) mask = masker.apply(scene.render(t, 6).frame);
  EXPECT_EQ(cv::countNonZero(mask(cv::Rect(0, scene.height - 20, scene.width, 20))), scene.width * 20);
}

TEST(ForegroundMask, HardInputsStayBounded) {
  test::SyntheticScene scene;
  ForegroundMasker masker = learnedMasker(scene);
  test::SyntheticFrame f = scene.render(0, 7);
  f.frame.depth.setTo(std::numeric_limits<float>::quiet_NaN());
  f.frame.depth(cv::Rect(0, 0, 50, 50)).setTo(std::numeric_limits<float>::infinity());
  const cv::Mat mask = masker.apply(f.frame);  // falls back to colour everywhere
  EXPECT_EQ(mask.type(), CV_8UC1);
  EXPECT_GT(score(mask, f.true_mask).recall, 0.9);
  // No background learned at all: the first frame is MOG2's background, no crash.
  ForegroundMasker fresh;
  EXPECT_EQ(fresh.apply(f.frame).size(), f.frame.depth.size());
  // A frame of another size is refused with a clear error.
  RgbdFrame small;
  small.colour = cv::Mat(10, 10, CV_8UC3, cv::Scalar::all(0));
  small.depth = cv::Mat(10, 10, CV_32FC1, cv::Scalar(1.0f));
  EXPECT_THROW(masker.apply(small), Error);
}

// A body 2 m away before a wall at 3 m, with an arm one pixel wide joined to it and a 2x2 speck
// of depth noise apart from it. The opening removes both; keep_attached_limbs brings back the arm
// (its region kept the body's pixels) and not the speck (its region kept none).
TEST(ForegroundMask, ThinLimbJoinedToABodyReturnsAndASpeckDoesNot) {
  const cv::Size size(160, 120);
  const auto frame = [&](bool visitor) {
    RgbdFrame f;
    f.colour = cv::Mat(size, CV_8UC3, cv::Scalar(128, 128, 128));
    f.depth = cv::Mat(size, CV_32FC1, cv::Scalar(3.0f));
    if (visitor) {
      f.depth(cv::Rect(60, 30, 20, 60)).setTo(2.0f);  // body
      f.depth(cv::Rect(80, 50, 25, 1)).setTo(2.0f);   // arm, one pixel wide
      f.depth(cv::Rect(20, 20, 2, 2)).setTo(2.0f);    // speck
    }
    return f;
  };
  const cv::Rect arm(80, 50, 25, 1), speck(20, 20, 2, 2);
  const auto masked = [&](bool keep) {
    ForegroundMaskConfig config;
    config.keep_attached_limbs = keep;
    ForegroundMasker masker(config);
    for (int t = 0; t < 5; ++t) masker.learnBackground(frame(false));
    return masker.apply(frame(true));
  };
  const cv::Mat with = masked(true), without = masked(false);
  EXPECT_EQ(cv::countNonZero(with(arm)), arm.area());
  EXPECT_EQ(cv::countNonZero(with(speck)), 0);
  EXPECT_LT(cv::countNonZero(without(arm)), arm.area() / 2);
  EXPECT_EQ(cv::countNonZero(without(speck)), 0);
  EXPECT_EQ(cv::countNonZero(with(cv::Rect(60, 30, 20, 60))), 20 * 60);
}

}  // namespace
}  // namespace holo::depthfilter
