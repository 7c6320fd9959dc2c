#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <string>

#include "holo/core/error.hpp"
#include "holo/depthfilter/foreground_scale.hpp"
#include "holo/depthfilter/full_size_outline.hpp"

namespace holo::depthfilter {
namespace {

// A visitor at 2 m reading in camera columns 0..visitor_last_column, the wall behind at 4 m; the
// reduced mask (scale 2) takes reduced columns 0..4 (camera columns 0..9) whole.
struct Scene {
  cv::Mat mask = cv::Mat::zeros(6, 10, CV_8UC1);
  cv::Mat depth = cv::Mat::zeros(6, 10, CV_32FC1);
  cv::Mat background = cv::Mat::zeros(6, 10, CV_32FC1);  // unknown: the filter's depth decides
  cv::Mat camera_depth = cv::Mat(12, 20, CV_32FC1, cv::Scalar(4.0f));
  Scene(int visitor_last_column) {
    mask.colRange(0, 5).setTo(255);
    depth.colRange(0, 5).setTo(2.01f);  // the filter's depth, one centimetre off the readings
    camera_depth.colRange(0, visitor_last_column + 1).setTo(2.0f);
  }
};

TEST(FullSizeOutline, TheCamerasReadingsRedrawTheOutlineWithTheFiltersDepth) {
  // The visitor ends at camera column 8: reduced column 4 (camera 8, 9) is half wall.
  const Scene half_wall(8);
  const FullSizeForeground out =
      fullSizeOutline(half_wall.mask, half_wall.depth, half_wall.background, half_wall.camera_depth, 2);
  ASSERT_EQ(out.mask.size(), cv::Size(20, 12));
  for (int y = 0; y < 12; ++y) {
    for (int x = 0; x <= 8; ++x) {
      EXPECT_EQ(out.mask.at<std::uint8_t>(y, x), 255) << x << "," << y;
      EXPECT_FLOAT_EQ(out.depth.at<float>(y, x), 2.01f);
    }
    for (int x = 9; x < 20; ++x) {
      EXPECT_EQ(out.mask.at<std::uint8_t>(y, x), 0) << x << "," << y;
      EXPECT_EQ(out.depth.at<float>(y, x), 0.0f);
    }
  }
  // The visitor reaches camera column 10, in reduced column 5 that the mask left out: the
  // readings there join it, column 11 (the wall) does not.
  const Scene beyond(10);
  const FullSizeForeground grown =
      fullSizeOutline(beyond.mask, beyond.depth, beyond.background, beyond.camera_depth, 2);
  for (int y = 0; y < 12; ++y) {
    EXPECT_EQ(grown.mask.at<std::uint8_t>(y, 9), 255);
    EXPECT_EQ(grown.mask.at<std::uint8_t>(y, 10), 255);
    EXPECT_FLOAT_EQ(grown.depth.at<float>(y, 10), 2.01f);
    EXPECT_EQ(grown.mask.at<std::uint8_t>(y, 11), 0);
  }
  // Each block repeated (expandedToFull) would have output the wall pixels 9 and missed 10.
  const cv::Mat blocks = expandedToFull(beyond.depth, cv::Size(20, 12));
  EXPECT_GT(blocks.at<float>(0, 9), 0.0f);
  EXPECT_EQ(blocks.at<float>(0, 10), 0.0f);
}

// A reading at the hall's learned depth is the hall even where it matches the foreground's depth
// (an object the colour found against a wall at its own depth).
TEST(FullSizeOutline, AReadingAtTheHallsDepthIsTheHall) {
  Scene scene(8);
  scene.camera_depth.setTo(2.0f);  // the wall at the visitor's depth
  scene.background.setTo(2.0f);
  const FullSizeForeground at_wall =
      fullSizeOutline(scene.mask, scene.depth, scene.background, scene.camera_depth, 2);
  EXPECT_EQ(at_wall.mask.at<std::uint8_t>(0, 10), 0);   // the blocks left out stay out
  EXPECT_EQ(at_wall.mask.at<std::uint8_t>(0, 9), 0);    // the outline block's pixels read the hall
  EXPECT_EQ(at_wall.mask.at<std::uint8_t>(0, 2), 255);  // interior blocks are repeated
  scene.background.setTo(0.0f);
  const FullSizeForeground unknown =
      fullSizeOutline(scene.mask, scene.depth, scene.background, scene.camera_depth, 2);
  EXPECT_EQ(unknown.mask.at<std::uint8_t>(0, 10), 255);  // without a hall the filter's depth decides
}

TEST(FullSizeOutline, APixelWithoutAReadingKeepsItsBlock) {
  Scene scene(8);
  scene.camera_depth.at<float>(3, 9) = 0.0f;
  scene.camera_depth.at<float>(4, 9) = std::numeric_limits<float>::quiet_NaN();
  const FullSizeForeground out =
      fullSizeOutline(scene.mask, scene.depth, scene.background, scene.camera_depth, 2);
  EXPECT_EQ(out.mask.at<std::uint8_t>(3, 9), 255);
  EXPECT_FLOAT_EQ(out.depth.at<float>(4, 9), 2.01f);
  EXPECT_EQ(out.mask.at<std::uint8_t>(5, 9), 0);  // its neighbour reads the wall
}

TEST(FullSizeOutline, InteriorAndOutsideBlocksAreRepeatedWhateverTheReadings) {
  Scene scene(8);
  scene.camera_depth.at<float>(2, 2) = 4.0f;   // a wrong reading inside the visitor
  scene.camera_depth.at<float>(2, 16) = 2.0f;  // a reading at the visitor's depth far outside
  const FullSizeForeground out =
      fullSizeOutline(scene.mask, scene.depth, scene.background, scene.camera_depth, 2);
  EXPECT_EQ(out.mask.at<std::uint8_t>(2, 2), 255);
  EXPECT_FLOAT_EQ(out.depth.at<float>(2, 2), 2.01f);
  EXPECT_EQ(out.mask.at<std::uint8_t>(2, 16), 0);
}

TEST(FullSizeOutline, MismatchedSizesOrTypesAreRefused) {
  const Scene scene(8);
  const cv::Mat wrong_size(13, 20, CV_32FC1, cv::Scalar(1.0f));
  EXPECT_THROW(fullSizeOutline(scene.mask, scene.depth, scene.background, wrong_size, 2), Error);
  EXPECT_THROW(fullSizeOutline(scene.mask, scene.depth, cv::Mat(), scene.camera_depth, 2), Error);
  cv::Mat wrong_type;
  scene.depth.convertTo(wrong_type, CV_64FC1);
  EXPECT_THROW(fullSizeOutline(scene.mask, wrong_type, scene.background, scene.camera_depth, 2), Error);
}

}  // namespace
}  // namespace holo::depthfilter
