#include <gtest/gtest.h>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/depthfilter/border_expansion.hpp"
#include "synthetic_rgbd.hpp"

namespace holo::depthfilter {
namespace {

// Border depths near the disc (1.5 m) and near the box (2 m) of the synthetic scene.
struct NearDepths {
  double near_disc = 0.0;
  double near_box = 0.0;
};

NearDepths borderDepths(const BorderLayer& layer, const test::SyntheticScene& scene) {
  double disc_sum = 0, box_sum = 0;
  long disc_n = 0, box_n = 0;
  const cv::Point2f c = scene.discCentre(10);
  for (int y = 0; y < layer.depth.rows; ++y)
    for (int x = 0; x < layer.depth.cols; ++x) {
      if (layer.weight.at<float>(y, x) <= 0.0f) continue;
      const double r = std::hypot(x - c.x, y - c.y);
      if (r > scene.disc_radius_px && r < scene.disc_radius_px + 4 && x > scene.box.br().x + 4) {
        disc_sum += layer.depth.at<float>(y, x), ++disc_n;
      } else if (x < scene.box.x && x > scene.box.x - 4 && y > scene.box.y && y < scene.box.br().y) {
        box_sum += layer.depth.at<float>(y, x), ++box_n;
      }
    }
  EXPECT_GT(disc_n, 10);
  EXPECT_GT(box_n, 10);
  return {disc_sum / double(disc_n), box_sum / double(box_n)};
}

TEST(BorderExpansion, WeightsLieBetweenZeroAndOneOutsideTheMask) {
  const test::SyntheticScene scene;
  const test::SyntheticFrame f = scene.render(10, 1);
  const BorderLayer layer = expandBorder(f.true_mask, f.true_depth, {});
  double lo = 0, hi = 0;
  cv::minMaxLoc(layer.weight, &lo, &hi);
  EXPECT_GE(lo, 0.0);
  EXPECT_LT(hi, 1.0);
  EXPECT_GT(hi, 0.3);
  cv::Mat inside = layer.weight.clone();
  inside.setTo(0.0f, f.true_mask == 0);
  EXPECT_EQ(cv::countNonZero(inside), 0);
  // The border is a band a few pixels wide: more than a 1-pixel ring, far less than the image.
  const int border = cv::countNonZero(layer.weight > 0.0f);
  EXPECT_GT(border, 4 * 200);
  EXPECT_LT(border, scene.width * scene.height / 4);
  // Every weighted pixel has a depth.
  EXPECT_EQ(cv::countNonZero((layer.weight > 0.0f) & (layer.depth <= 0.0f)), 0);
}

TEST(BorderExpansion, NearestDepthKeepsObjectsApartMeanEdgeDoesNot) {
  const test::SyntheticScene scene;
  const test::SyntheticFrame f = scene.render(10, 1);
  const NearDepths nearest = borderDepths(expandBorder(f.true_mask, f.true_depth, {}), scene);
  EXPECT_NEAR(nearest.near_disc, 1.5, 0.02);
  EXPECT_NEAR(nearest.near_box, 2.0, 0.02);
  BorderExpansionConfig paper;
  paper.depth = BorderDepth::MeanEdge;
  const NearDepths mean = borderDepths(expandBorder(f.true_mask, f.true_depth, paper), scene);
  EXPECT_NEAR(mean.near_disc, mean.near_box, 1e-6);  // one d_bor for every border pixel
  EXPECT_GT(mean.near_disc, 1.5);
  EXPECT_LT(mean.near_disc, 2.0);
}

TEST(BorderExpansion, DegenerateMasksGiveNoBorder) {
  const cv::Mat depth(40, 60, CV_32FC1, cv::Scalar(2.0f));
  const cv::Mat empty = cv::Mat::zeros(40, 60, CV_8UC1);
  EXPECT_EQ(cv::countNonZero(expandBorder(empty, depth, {}).weight), 0);
  const cv::Mat full(40, 60, CV_8UC1, cv::Scalar(255));
  EXPECT_EQ(cv::countNonZero(expandBorder(full, depth, {}).weight), 0);  // nothing outside
  cv::Mat some = empty.clone();
  some(cv::Rect(20, 10, 10, 10)).setTo(255);
  const cv::Mat no_depth = cv::Mat::zeros(40, 60, CV_32FC1);
  EXPECT_EQ(cv::countNonZero(expandBorder(some, no_depth, {}).weight), 0);
  cv::Mat nan_depth(40, 60, CV_32FC1, cv::Scalar(std::nanf("")));
  EXPECT_EQ(cv::countNonZero(expandBorder(some, nan_depth, {}).weight), 0);
  BorderExpansionConfig off;
  off.levels = 0;
  EXPECT_EQ(cv::countNonZero(expandBorder(some, depth, off).weight), 0);
  EXPECT_GT(cv::countNonZero(expandBorder(some, depth, {}).weight), 0);
  EXPECT_THROW(expandBorder(some, cv::Mat(10, 10, CV_32FC1), {}), Error);
}

// expandBorder works only on the mask's bounding box grown by the blur's reach. Against the
// definition computed over the whole frame (blurred mask from the Gaussian pyramid, weight in
// (0,1) outside the mask, depth of the nearest foreground pixel with a depth by brute force):
// same border pixels and weights, bit for bit, everywhere, for a mask in the middle and ones at
// corners, on a frame whose sides are multiples of the pyramid's cell (the blur then works on a
// region around the mask) and on one whose sides are not. Every border and mask pixel lies in
// borderBox (the back-projection reads only that).
TEST(BorderExpansion, WorkingOnTheMasksNeighbourhoodMissesNoBorderPixel) {
  EXPECT_TRUE(borderBox(cv::Mat::zeros(120, 200, CV_8UC1), {}).empty());
  for (const cv::Size frame : {cv::Size(200, 120), cv::Size(203, 121)})
    for (const cv::Rect blob :
         {cv::Rect(90, 60, 30, 40), cv::Rect(0, 0, 12, 9),
          cv::Rect(frame.width - 20, frame.height - 13, 20, 13), cv::Rect(37, 3, 5, 70)}) {
      cv::Mat mask = cv::Mat::zeros(frame, CV_8UC1), depth = cv::Mat::zeros(frame, CV_32FC1);
      mask(blob).setTo(255);
      depth(blob).setTo(1.5f);
      const BorderExpansionConfig config;
      const BorderLayer layer = expandBorder(mask, depth, config);
      const cv::Rect box = borderBox(mask, config);
      cv::Mat level;
      mask.convertTo(level, CV_32FC1, 1.0 / 255.0);
      for (int l = 0; l < config.levels; ++l) cv::pyrDown(level, level);
      cv::Mat blurred;
      cv::resize(level, blurred, mask.size(), 0, 0, cv::INTER_LINEAR);
      long border = 0;
      for (int y = 0; y < mask.rows; ++y)
        for (int x = 0; x < mask.cols; ++x) {
          const float w = blurred.at<float>(y, x);
          const bool expected = mask.at<std::uint8_t>(y, x) == 0 && w >= config.min_weight && w < 1.0f;
          border += expected;
          if (expected || mask.at<std::uint8_t>(y, x) != 0) {
            ASSERT_TRUE(box.contains({x, y})) << x << "," << y;
          }
          ASSERT_EQ(layer.weight.at<float>(y, x) > 0.0f, expected) << x << "," << y;
          if (!expected) continue;
          EXPECT_EQ(layer.weight.at<float>(y, x), w);
          EXPECT_FLOAT_EQ(layer.depth.at<float>(y, x), 1.5f);
        }
      EXPECT_GT(border, 2L * (blob.width + blob.height));  // a ring, not a line
    }
}

}  // namespace
}  // namespace holo::depthfilter
