#include <gtest/gtest.h>
#include <sstream>

#include "holo/core/image.hpp"
#include "holo/core/stats.hpp"

namespace holo {
namespace {

TEST(Image, SrgbRoundTripWithinOneStep) {
  cv::Mat bgr8(16, 16, CV_8UC3);
  for (int i = 0; i < 256; ++i)
    bgr8.at<cv::Vec3b>(i / 16, i % 16) = cv::Vec3b(uchar(i), uchar(255 - i), uchar(i / 2));
  const cv::Mat back = linearToSrgb8(srgb8ToLinear(bgr8));
  EXPECT_LE(cv::norm(back, bgr8, cv::NORM_INF), 1.0);
}

TEST(Image, LinearToSrgbClampsAndSurvivesNonFinite) {
  cv::Mat hdr(1, 3, CV_32FC3);
  hdr.at<cv::Vec3f>(0, 0) = cv::Vec3f(-1.0f, 1e30f, std::numeric_limits<float>::quiet_NaN());
  hdr.at<cv::Vec3f>(0, 1) = cv::Vec3f(0.5f, 0.5f, 0.5f);
  hdr.at<cv::Vec3f>(0, 2) = cv::Vec3f(0.25f, 0.25f, 0.25f);
  const cv::Mat out = linearToSrgb8(hdr, 2.0f);
  EXPECT_EQ(out.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 255, 0));
  EXPECT_EQ(out.at<cv::Vec3b>(0, 1), cv::Vec3b(255, 255, 255));  // 0.5 x exposure 2 = 1
  EXPECT_EQ(out.at<cv::Vec3b>(0, 2)[0], 188);                    // sRGB(0.5) = 0.7354
}

TEST(Image, RgbHelpersSwapChannelOrder) {
  cv::Mat img(1, 1, CV_32FC3, cv::Scalar(1, 2, 3));  // stored B=1, G=2, R=3
  EXPECT_EQ(rgbAt(img, 0, 0), vec3(3, 2, 1));
  setRgb(img, 0, 0, {4, 5, 6});
  EXPECT_EQ(img.at<cv::Vec3f>(0, 0), cv::Vec3f(6, 5, 4));
}

TEST(Stats, CountersAccumulateAndPrintByCategory) {
  stats::resetAll();
  stats::add("Test/Things counted", 3);
  stats::add("Test/Things counted", 4);
  EXPECT_EQ(stats::snapshot().at("Test/Things counted"), 7);
  std::ostringstream out;
  stats::print(out);
  EXPECT_NE(out.str().find("Things counted"), std::string::npos);
  EXPECT_NE(out.str().find("7"), std::string::npos);
}

}  // namespace
}  // namespace holo
