#include <gtest/gtest.h>

#include "holo/depthfilter/reused_zero_image.hpp"

namespace holo::depthfilter {
namespace {

TEST(ReusedZeroImage, UnsharedBufferIsReusedWithTheWrittenBoxCleared) {
  ReusedZeroImage image;
  const cv::Size size(64, 48);
  cv::Mat first = image.next(size, CV_32FC1);
  ASSERT_EQ(cv::countNonZero(first), 0);
  first(cv::Rect(10, 5, 20, 8)).setTo(3.0f);
  first(cv::Rect(40, 30, 4, 4)).setTo(-1.0f);
  image.written(cv::Rect(10, 5, 20, 8));
  image.written(cv::Rect(40, 30, 4, 4));
  const uchar* buffer = first.data;
  first.release();  // nobody else holds it now
  const cv::Mat second = image.next(size, CV_32FC1);
  EXPECT_EQ(second.data, buffer);
  EXPECT_EQ(cv::countNonZero(second), 0);
}

TEST(ReusedZeroImage, AnImageStillHeldIsNeverChanged) {
  ReusedZeroImage image;
  const cv::Size size(32, 32);
  cv::Mat kept = image.next(size, CV_8UC1);
  kept(cv::Rect(4, 4, 8, 8)).setTo(7);
  image.written(cv::Rect(4, 4, 8, 8));
  cv::Mat next = image.next(size, CV_8UC1);
  EXPECT_NE(next.data, kept.data);
  EXPECT_EQ(cv::countNonZero(next), 0);
  EXPECT_EQ(cv::countNonZero(kept), 64);
  next.setTo(9);  // written everywhere but declared nowhere would break the contract; the kept one stays
  EXPECT_EQ(cv::countNonZero(kept == 7), 64);
}

TEST(ReusedZeroImage, ANewSizeOrTypeGetsAFreshZeroImage) {
  ReusedZeroImage image;
  cv::Mat a = image.next(cv::Size(16, 16), CV_32FC1);
  a.setTo(1.0f);
  image.written(cv::Rect(0, 0, 16, 16));
  a.release();
  const cv::Mat b = image.next(cv::Size(16, 16), CV_32FC2);
  EXPECT_EQ(b.type(), CV_32FC2);
  EXPECT_EQ(cv::countNonZero(b.reshape(1)), 0);
  const cv::Mat c = image.next(cv::Size(8, 16), CV_32FC2);
  EXPECT_EQ(c.size(), cv::Size(8, 16));
  EXPECT_EQ(cv::countNonZero(c.reshape(1)), 0);
}

}  // namespace
}  // namespace holo::depthfilter
