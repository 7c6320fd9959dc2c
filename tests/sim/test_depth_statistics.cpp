#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "holo/core/error.hpp"
#include "holo/sim/depth_statistics.hpp"

namespace holo::sim {
namespace {

// A 10 x 10 hole and five single missing pixels on a flat 2 m wall: no depth edge anywhere, so no
// hole is an edge hole, and the hole sizes fall in their classes.
TEST(DepthStatistics, CountsHolesAndTheirSizes) {
  cv::Mat depth(100, 100, CV_32FC1, cv::Scalar(2.0f));
  depth(cv::Rect(40, 40, 10, 10)).setTo(0.0f);
  for (int k = 0; k < 5; ++k) depth.at<float>(5 + 10 * k, 10) = 0.0f;
  const DepthStatistics s = measureDepthStatistics(depth);
  EXPECT_DOUBLE_EQ(s.hole_fraction, 105.0 / 10000.0);
  EXPECT_EQ(s.hole_components, 6);
  EXPECT_DOUBLE_EQ(s.edge_hole_share, 0.0);
  EXPECT_DOUBLE_EQ(s.hole_size_share[0], 5.0 / 105.0);    // single pixels
  EXPECT_DOUBLE_EQ(s.hole_size_share[2], 100.0 / 105.0);  // 11-100 pixels
  EXPECT_LT(s.person_hole_fraction, 0.0);                 // no mask given
  EXPECT_FLOAT_EQ(static_cast<float>(s.median_depth), 2.0f);
}

// A step from 1 m to 3 m with a 6-pixel gap (a projector shadow) beside it and a hole far from
// it: the gap's holes are edge holes even though the edge's two sides are 6 pixels apart.
TEST(DepthStatistics, HolesBesideADepthEdgeAreEdgeHoles) {
  cv::Mat depth(60, 100, CV_32FC1, cv::Scalar(3.0f));
  depth(cv::Rect(50, 0, 50, 60)).setTo(1.0f);
  depth(cv::Rect(44, 0, 6, 60)).setTo(0.0f);
  depth(cv::Rect(5, 20, 4, 4)).setTo(0.0f);
  const DepthStatistics s = measureDepthStatistics(depth);
  EXPECT_DOUBLE_EQ(s.edge_hole_share, 360.0 / 376.0);
}

TEST(DepthStatistics, HoleFractionsOnAndOffThePersonMask) {
  cv::Mat depth(50, 50, CV_32FC1, cv::Scalar(2.0f));
  cv::Mat person = cv::Mat::zeros(50, 50, CV_8UC1);
  person(cv::Rect(0, 0, 10, 50)).setTo(255);  // 500 px
  depth(cv::Rect(0, 0, 10, 10)).setTo(0.0f);  // 100 holes on the person
  depth(cv::Rect(30, 30, 4, 5)).setTo(0.0f);  // 20 holes elsewhere
  const DepthStatistics s = measureDepthStatistics(depth, person);
  EXPECT_DOUBLE_EQ(s.person_hole_fraction, 0.2);
  EXPECT_DOUBLE_EQ(s.other_hole_fraction, 20.0 / 2000.0);
}

// Gaussian noise of 5 mm on a tilted plane around 2 m: the plane fits take the tilt out and the
// median window residual is the noise (the median of a 46-dof sample deviation is ~0.5% low).
TEST(DepthStatistics, NoiseIsThePlaneResidual) {
  cv::Mat depth(240, 320, CV_32FC1);
  cv::RNG rng(7);
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x)
      depth.at<float>(y, x) = 1.9f + 0.0005f * static_cast<float>(x) + 0.0002f * static_cast<float>(y) +
                              static_cast<float>(rng.gaussian(0.005));
  const DepthStatistics s = measureDepthStatistics(depth);
  EXPECT_LT(s.noise[0], 0.0);  // nothing near 1 m
  EXPECT_LT(s.noise[2], 0.0);  // nor near 4 m
  EXPECT_GT(s.noise_windows[1], 3000);
  EXPECT_NEAR(s.noise[1], 0.005, 0.00015);
}

TEST(DepthStatistics, BadDepthFilesNameTheFile) {
  try {
    loadDepthPng("/nonexistent/depth.png", 5000.0);
    FAIL() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/depth.png");
    EXPECT_EQ(e.field(), "depth");
  }
}

}  // namespace
}  // namespace holo::sim
