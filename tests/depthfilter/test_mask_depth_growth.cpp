#include <gtest/gtest.h>

#include "holo/core/error.hpp"
#include "holo/depthfilter/mask_depth_growth.hpp"

namespace holo::depthfilter {
namespace {

// A visitor at 2 m in the mask (columns 40..59); to its right, where the empty hall read nothing,
// the sensor reads the visitor's arm at 2.02 m (columns 60..79, which the colour missed) and below
// it a far hall reading at 6 m beside the mask (rows 50..59). To its left the background depth is
// known (4 m) and the sensor reads 2.01 m: the depth comparison decides there, not the growth.
struct Scene {
  cv::Mat mask = cv::Mat::zeros(60, 120, CV_8UC1);
  cv::Mat depth = cv::Mat::zeros(60, 120, CV_32FC1);
  cv::Mat background = cv::Mat::zeros(60, 120, CV_32FC1);
  Scene() {
    mask(cv::Rect(40, 0, 20, 50)).setTo(255);
    depth(cv::Rect(40, 0, 20, 50)).setTo(2.0f);
    depth(cv::Rect(60, 0, 20, 50)).setTo(2.02f);  // the arm
    depth(cv::Rect(40, 50, 40, 10)).setTo(6.0f);  // the hall below, unread when empty
    background(cv::Rect(0, 0, 40, 60)).setTo(4.0f);
    depth(cv::Rect(0, 0, 40, 60)).setTo(2.01f);
  }
};

TEST(MaskDepthGrowth, GrowsAlongTheVisitorsSurfaceWhereTheBackgroundIsUnknown) {
  Scene s;
  cv::Mat scratch;
  growMaskIntoUnknownBackground(s.mask, s.depth, s.background, {.steps = 5}, scratch);
  // The arm joins by five pixels, one a step; the rest of it stays out.
  EXPECT_EQ(cv::countNonZero(s.mask(cv::Rect(60, 0, 5, 50))), 5 * 50);
  EXPECT_EQ(cv::countNonZero(s.mask(cv::Rect(65, 0, 15, 50))), 0);
  // The far hall below touches the mask but does not continue its surface.
  EXPECT_EQ(cv::countNonZero(s.mask(cv::Rect(40, 50, 40, 10))), 0);
  // Where the background depth is known the growth leaves the pixel to the depth comparison.
  EXPECT_EQ(cv::countNonZero(s.mask(cv::Rect(0, 0, 40, 60))), 0);
}

TEST(MaskDepthGrowth, ZeroStepsLeavesTheMaskAndBadInputIsRefused) {
  Scene s;
  const cv::Mat before = s.mask.clone();
  cv::Mat scratch;
  growMaskIntoUnknownBackground(s.mask, s.depth, s.background, {.steps = 0}, scratch);
  EXPECT_EQ(cv::countNonZero(s.mask != before), 0);
  cv::Mat small_depth = cv::Mat::zeros(10, 10, CV_32FC1);
  EXPECT_THROW(growMaskIntoUnknownBackground(s.mask, small_depth, s.background, {.steps = 1}, scratch),
               Error);
}

}  // namespace
}  // namespace holo::depthfilter
