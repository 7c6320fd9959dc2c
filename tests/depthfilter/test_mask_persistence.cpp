// MaskPersistence on hand-made 8x6 frames: a foreground pixel that loses its depth stays
// foreground while its colour is the precursor's, and only there.
#include <gtest/gtest.h>

#include "holo/core/error.hpp"
#include "holo/depthfilter/mask_persistence.hpp"

namespace holo::depthfilter {
namespace {

constexpr int kW = 8, kH = 6;

RgbdFrame frameWith(const cv::Vec3b& colour, float depth) {
  RgbdFrame f;
  f.colour = cv::Mat(kH, kW, CV_8UC3, cv::Scalar(200, 200, 200));
  f.depth = cv::Mat(kH, kW, CV_32FC1, cv::Scalar(3.0f));
  f.colour.at<cv::Vec3b>(2, 3) = colour;
  f.depth.at<float>(2, 3) = depth;
  return f;
}

cv::Mat maskAt(int x, int y) {
  cv::Mat m = cv::Mat::zeros(kH, kW, CV_8UC1);
  if (x >= 0) m.at<std::uint8_t>(y, x) = 255;
  return m;
}

// The flow of every pixel: one pixel to the left (the visitor moved right by one pixel).
cv::Mat flowLeft() {
  return cv::Mat(kH, kW, CV_32FC2, cv::Scalar(-1.0f, 0.0f));
}

TEST(MaskPersistence, SensorlessPixelWhosePrecursorWasForegroundStaysForeground) {
  MaskPersistence persistence;
  const cv::Vec3b visitor(40, 60, 90);
  RgbdFrame first = frameWith(visitor, 2.0f);
  // The visitor was at (2, 2) and is at (3, 2) now, without depth: the colour still matches.
  first.colour.at<cv::Vec3b>(2, 2) = visitor;
  cv::Mat mask = maskAt(2, 2);
  persistence.extend(mask, first, cv::Mat());
  EXPECT_EQ(cv::countNonZero(mask), 1);  // no flow yet: unchanged
  cv::Mat now = maskAt(-1, 0);
  persistence.extend(now, frameWith(visitor + cv::Vec3b(5, 5, 5), 0.0f), flowLeft());
  EXPECT_EQ(now.at<std::uint8_t>(2, 3), 255);
  EXPECT_EQ(cv::countNonZero(now), 1);
  // It carries over frames while the sensor reads nothing and the colour holds.
  cv::Mat next = maskAt(-1, 0);
  persistence.extend(next, frameWith(visitor, 0.0f), cv::Mat(kH, kW, CV_32FC2, cv::Scalar(0.0f, 0.0f)));
  EXPECT_EQ(next.at<std::uint8_t>(2, 3), 255);
}

TEST(MaskPersistence, ColourChangeOrValidDepthReleasesThePixel) {
  const cv::Vec3b visitor(40, 60, 90);
  for (const bool by_depth : {false, true}) {
    MaskPersistence persistence;
    cv::Mat mask = maskAt(3, 2);
    persistence.extend(mask, frameWith(visitor, 2.0f), cv::Mat());
    // The wall behind the visitor (its colour) without depth, or the visitor's colour with a depth
    // the mask judged background: neither persists.
    const RgbdFrame now = by_depth ? frameWith(visitor, 3.0f) : frameWith(cv::Vec3b(200, 200, 200), 0.0f);
    cv::Mat next = maskAt(-1, 0);
    persistence.extend(next, now, cv::Mat(kH, kW, CV_32FC2, cv::Scalar(0.0f, 0.0f)));
    EXPECT_EQ(cv::countNonZero(next), 0) << (by_depth ? "valid depth" : "colour changed");
  }
}

TEST(MaskPersistence, SwitchedOffOrResetChangesNothing) {
  const cv::Vec3b visitor(40, 60, 90);
  for (const bool reset : {false, true}) {
    MaskPersistence persistence(MaskPersistenceConfig{.enabled = reset, .colour_max = 30.0f});
    cv::Mat mask = maskAt(3, 2);
    persistence.extend(mask, frameWith(visitor, 2.0f), cv::Mat());
    if (reset) persistence.reset();
    cv::Mat next = maskAt(-1, 0);
    persistence.extend(next, frameWith(visitor, 0.0f), cv::Mat(kH, kW, CV_32FC2, cv::Scalar(0.0f, 0.0f)));
    EXPECT_EQ(cv::countNonZero(next), 0);
  }
}

TEST(MaskPersistence, BadInputIsRefused) {
  EXPECT_THROW(MaskPersistence(MaskPersistenceConfig{.enabled = true, .colour_max = -1.0f}), Error);
  EXPECT_THROW(MaskPersistence(MaskPersistenceConfig{.enabled = true, .colour_max = 800.0f}), Error);
  MaskPersistence persistence;
  cv::Mat mask = maskAt(3, 2);
  persistence.extend(mask, frameWith(cv::Vec3b(1, 2, 3), 2.0f), cv::Mat());
  cv::Mat wrong_flow(kH, kW, CV_32FC1, cv::Scalar(0.0f));
  EXPECT_THROW(persistence.extend(mask, frameWith(cv::Vec3b(1, 2, 3), 0.0f), wrong_flow), Error);
  cv::Mat small = cv::Mat::zeros(2, 2, CV_8UC1);
  EXPECT_THROW(persistence.extend(small, frameWith(cv::Vec3b(1, 2, 3), 0.0f), cv::Mat()), Error);
}

}  // namespace
}  // namespace holo::depthfilter
