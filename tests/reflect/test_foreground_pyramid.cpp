#include "holo/reflect/foreground_pyramid.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "holo/core/error.hpp"

namespace holo::reflect {
namespace {

// The blur a read delivers, measured on an impulse: the variance of the response along x.
TEST(ForegroundPyramid, MeasuredBlurMatchesTheDerivedSigma) {
  cv::Mat colour(256, 256, CV_32FC3, cv::Scalar::all(0));
  cv::Mat mask(256, 256, CV_32FC1, cv::Scalar(0));
  colour.at<cv::Vec3f>(128, 128) = cv::Vec3f(1, 1, 1);
  mask.at<float>(128, 128) = 1.0f;
  const ForegroundPyramid pyramid(colour, mask, 6);
  for (int level = 1; level < 6; ++level) {
    double sum = 0.0, mean = 0.0, sq = 0.0;
    for (int x = 0; x < 256; ++x) {
      const double w = pyramid.sample(vec2(float(x), 128.0f), float(level)).weight;
      sum += w;
      mean += w * x;
      sq += w * double(x) * x;
    }
    mean /= sum;
    const double sigma = std::sqrt(sq / sum - mean * mean);
    EXPECT_NEAR(sigma, pyramidSigmaPx(float(level)), 0.2 * pyramidSigmaPx(float(level))) << "level " << level;
    EXPECT_NEAR(pyramidLevelForSigma(pyramidSigmaPx(float(level))), float(level), 1e-3f);
  }
}

TEST(ForegroundPyramid, PremultipliedBlurKeepsForegroundColourAndWeightsItsCoverage) {
  // A red foreground disc on a bright green background: the background must not bleed in.
  cv::Mat colour(128, 128, CV_32FC3, cv::Scalar(0, 5, 0));
  cv::Mat mask(128, 128, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x)
      if ((x - 64) * (x - 64) + (y - 64) * (y - 64) < 30 * 30) {
        colour.at<cv::Vec3f>(y, x) = cv::Vec3f(0, 0, 2);
        mask.at<std::uint8_t>(y, x) = 255;
      }
  const ForegroundPyramid pyramid(colour, mask, 5);
  for (float level : {0.0f, 2.5f, 4.0f}) {
    const ForegroundSample edge = pyramid.sample(vec2(64.0f + 29.5f, 64.0f), level);
    EXPECT_GT(edge.weight, 0.1f);
    EXPECT_LT(edge.weight, 0.9f);
    EXPECT_NEAR(edge.radiance.r, 2.0f, 1e-3f);
    EXPECT_NEAR(edge.radiance.g, 0.0f, 1e-3f);
    const ForegroundSample centre = pyramid.sample(vec2(64.0f), level);
    EXPECT_GT(centre.weight, 0.9f);
  }
  EXPECT_EQ(pyramid.sample(vec2(2.0f), 0.0f).weight, 0.0f);
  EXPECT_EQ(pyramid.sample(vec2(2.0f), 0.0f).radiance, vec3(0.0f));
}

TEST(ForegroundPyramid, NonFiniteInputsAreRepairedAndReadsStayBounded) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  cv::Mat colour(16, 16, CV_32FC3, cv::Scalar(nan, inf, 1));
  cv::Mat mask(16, 16, CV_32FC1, cv::Scalar(nan));
  mask.at<float>(3, 3) = inf;
  mask.at<float>(4, 4) = 7.0f;
  const ForegroundPyramid pyramid(colour, mask, 3);
  for (float level : {-5.0f, 0.0f, 1.5f, 99.0f, nan})
    for (const vec2 p : {vec2(4.0f), vec2(-100.0f), vec2(nan, 0.0f), vec2(1e30f)}) {
      const ForegroundSample s = pyramid.sample(p, level);
      EXPECT_TRUE(isFinite(s.radiance));
      EXPECT_GE(s.weight, 0.0f);
      EXPECT_LE(s.weight, 1.0f);
    }
  EXPECT_NEAR(pyramid.sample(vec2(4.0f), 0.0f).weight, 1.0f, 1e-6f);
}

TEST(ForegroundPyramid, RejectsMismatchedInputs) {
  const cv::Mat colour(8, 8, CV_32FC3, cv::Scalar::all(0));
  EXPECT_THROW(ForegroundPyramid(colour, cv::Mat(8, 9, CV_32FC1), 2), InputError);
  EXPECT_THROW(ForegroundPyramid(colour, cv::Mat(8, 8, CV_16UC1), 2), InputError);
  EXPECT_THROW(ForegroundPyramid(colour, cv::Mat(8, 8, CV_32FC1), 0), InputError);
  EXPECT_THROW(ForegroundPyramid(cv::Mat(8, 8, CV_8UC3), cv::Mat(8, 8, CV_32FC1), 2), InputError);
}

TEST(ForegroundLevel, GrowsWithRoughnessAndTravelAndStaysInRange) {
  EXPECT_EQ(foregroundLevel(0.0f, 1.0f, 1.0f, 600.0f, 6), 0.0f);  // a mirror reads level 0
  float previous = 0.0f;
  for (float r : {0.1f, 0.2f, 0.4f, 0.7f, 1.0f}) {
    const float l = foregroundLevel(r, 0.5f, 1.5f, 600.0f, 8);
    EXPECT_GE(l, previous);
    previous = l;
  }
  EXPECT_GT(previous, 5.0f);
  EXPECT_LT(foregroundLevel(0.3f, 0.2f, 1.5f, 600.0f, 8), foregroundLevel(0.3f, 0.8f, 1.5f, 600.0f, 8));
  // Roughness 0.3: alpha 0.09, lobe sqrt(2) 0.09 rad; 0.5 m travel seen from 1.5 m at f = 600 px
  // spreads sigma = 0.5 tan(0.127) 600 / 1.5 = 25.6 px -> L = log2((25.6^2 + 0.25) 2.4) / 2.
  const float sigma = 0.5f * std::tan(std::sqrt(2.0f) * 0.09f) * 600.0f / 1.5f;
  EXPECT_NEAR(foregroundLevel(0.3f, 0.5f, 1.5f, 600.0f, 12), 0.5f * std::log2((sigma * sigma + 0.25f) * 2.4f),
              1e-4f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(foregroundLevel(nan, nan, 1.0f, 600.0f, 6), 0.0f);
  EXPECT_EQ(foregroundLevel(1.0f, 1e30f, 1e-30f, 600.0f, 6), 5.0f);  // overflow: the top level
  EXPECT_LE(foregroundLevel(1.0f, 100.0f, 0.01f, 600.0f, 6), 5.0f);
}

}  // namespace
}  // namespace holo::reflect
