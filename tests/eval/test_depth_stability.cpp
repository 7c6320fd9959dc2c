// DepthStabilityMeter on frames whose answers are known by construction.
#include <gtest/gtest.h>
#include <cmath>

#include "holo/core/error.hpp"
#include "holo/eval/depth_stability.hpp"

namespace holo::eval {
namespace {

const cv::Size kSize(80, 60);
const cv::Rect kPerson(20, 10, 30, 40);

cv::Mat personMask(const cv::Rect& where = kPerson) {
  cv::Mat mask = cv::Mat::zeros(kSize, CV_8UC1);
  mask(where).setTo(255);
  return mask;
}

// A wall at 3 m with a person at 1.5 m.
cv::Mat scene(const cv::Rect& person = kPerson) {
  cv::Mat depth(kSize, CV_32FC1, cv::Scalar(3.0f));
  depth(person).setTo(1.5f);
  return depth;
}

// A 10 x 10 patch of the person that is a hole every other frame flickers; the filter's output
// that holds it does not. 100 of the 1200 person pixels switch in each of 9 frame pairs.
TEST(DepthStability, CountsHolesThatComeAndGo) {
  DepthStabilityMeter meter;
  for (int t = 0; t < 10; ++t) {
    cv::Mat raw = scene();
    if (t % 2) raw(cv::Rect(30, 20, 10, 10)).setTo(0.0f);
    cv::Mat filtered = cv::Mat::zeros(kSize, CV_32FC1);
    scene().copyTo(filtered, personMask());
    meter.addFrame(raw, personMask(), filtered);
  }
  const DepthStabilityFigures f = meter.figures();
  EXPECT_EQ(f.frame_pairs, 9);
  EXPECT_EQ(f.raw.pixel_pairs, 9 * 1200);
  EXPECT_DOUBLE_EQ(f.raw.hole_flicker, 100.0 / 1200.0);
  EXPECT_DOUBLE_EQ(f.filtered.hole_flicker, 0.0);
  EXPECT_DOUBLE_EQ(f.filtered.edge_jitter_px, 0.0);  // a still silhouette
  EXPECT_GT(f.raw.edge_jitter_px, 0.3);              // the patch's border comes and goes
  EXPECT_DOUBLE_EQ(f.background.hole_flicker, 0.0);
  EXPECT_EQ(cv::countNonZero(meter.rawFlickerCount() == 9), 100);
}

// Gaussian noise of 4 mm on the still background is its temporal noise; the person's pixels
// (foreground in every frame) are not background.
TEST(DepthStability, BackgroundNoiseIsThePerPixelStandardDeviation) {
  DepthStabilityMeter meter;
  cv::RNG rng(7);
  for (int t = 0; t < 40; ++t) {
    cv::Mat noise(kSize, CV_32FC1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.004);
    cv::Mat raw = scene() + noise;
    raw(kPerson).setTo(1.5f);
    meter.addFrame(raw, personMask(), cv::Mat::zeros(kSize, CV_32FC1));
  }
  const DepthStabilityFigures f = meter.figures();
  EXPECT_EQ(f.background_noise_pixels, kSize.area() - kPerson.area());
  EXPECT_NEAR(f.background_noise_mm, 4.0, 0.2);
  for (double at_depth : f.background_noise_mm_at) EXPECT_TRUE(std::isnan(at_depth));  // all at 3 m
  EXPECT_DOUBLE_EQ(f.background.edge_jitter_px, 0.0);  // the wall's edges (the person's outline) stay
}

// A person moving 2 px per frame: their edges move, so the jitter is about what they moved on
// the sides across the motion and 0 along it; standing still gives 0.
TEST(DepthStability, EdgeJitterFollowsMovingEdges) {
  DepthStabilityMeter moving, still;
  for (int t = 0; t < 6; ++t) {
    const cv::Rect at(kPerson.x + 2 * t, kPerson.y, kPerson.width, kPerson.height);
    cv::Mat filtered = cv::Mat::zeros(kSize, CV_32FC1);
    scene(at).copyTo(filtered, personMask(at));
    moving.addFrame(scene(at), personMask(at), filtered);
    still.addFrame(scene(), personMask(), cv::Mat::zeros(kSize, CV_32FC1));
  }
  const DepthStabilityFigures m = moving.figures(), s = still.figures();
  EXPECT_GT(m.raw.edge_jitter_px, 0.3);
  EXPECT_LT(m.raw.edge_jitter_px, 2.0);
  EXPECT_DOUBLE_EQ(s.raw.edge_jitter_px, 0.0);
  EXPECT_TRUE(std::isnan(s.filtered.edge_jitter_px));  // the filter gave nothing: nothing to measure
}

TEST(DepthStability, MismatchedFramesAreAnError) {
  DepthStabilityMeter meter;
  EXPECT_THROW(meter.addFrame(scene(), personMask(), cv::Mat::zeros(10, 10, CV_32FC1)), Error);
  meter.addFrame(scene(), personMask(), scene());
  EXPECT_THROW(meter.addFrame(cv::Mat::zeros(10, 10, CV_32FC1), cv::Mat::zeros(10, 10, CV_8UC1),
                              cv::Mat::zeros(10, 10, CV_32FC1)),
               Error);
  EXPECT_TRUE(std::isnan(meter.figures().raw.hole_flicker));  // one frame: no pair
}

}  // namespace
}  // namespace holo::eval
