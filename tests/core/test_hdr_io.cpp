#include <gtest/gtest.h>
#include <fstream>
#include <limits>

#include "holo/core/error.hpp"
#include "holo/core/hdr_io.hpp"
#include "shared_data.hpp"

namespace holo {
namespace {

TEST(HdrIo, RepairsNanInfAndNegativePixelsAndCountsThem) {
  cv::Mat img(4, 8, CV_32FC3, cv::Scalar(0.5f, 1.0f, 2.0f));
  img.at<cv::Vec3f>(0, 0)[0] = std::numeric_limits<float>::quiet_NaN();
  img.at<cv::Vec3f>(1, 1)[1] = std::numeric_limits<float>::infinity();
  img.at<cv::Vec3f>(2, 2)[2] = -3.0f;
  img.at<cv::Vec3f>(3, 3)[0] = -std::numeric_limits<float>::infinity();
  img.at<cv::Vec3f>(3, 4)[2] = 7.0f;
  const auto dir = test::scratchDir("hdr_repair");
  saveHdr(dir / "bad.exr", img);
  const HdrImage loaded = loadHdr(dir / "bad.exr");
  EXPECT_EQ(loaded.repaired.nan, 1);
  EXPECT_EQ(loaded.repaired.inf, 2);
  EXPECT_EQ(loaded.repaired.negative, 1);
  EXPECT_EQ(loaded.pixels.at<cv::Vec3f>(0, 0)[0], 0.0f);
  EXPECT_EQ(loaded.pixels.at<cv::Vec3f>(1, 1)[1], 7.0f);  // +Inf -> largest finite value
  EXPECT_EQ(loaded.pixels.at<cv::Vec3f>(2, 2)[2], 0.0f);
  EXPECT_EQ(loaded.pixels.at<cv::Vec3f>(3, 3)[0], 0.0f);
  EXPECT_TRUE(cv::checkRange(loaded.pixels));
}

TEST(HdrIo, ExrRoundTripKeepsFullFloatRange) {
  cv::Mat img(3, 5, CV_32FC3);
  cv::randu(img, 0.0f, 1.0f);
  img.at<cv::Vec3f>(1, 2) = cv::Vec3f(1e5f, 2.5e5f, 3e-6f);  // above half precision's range
  const auto dir = test::scratchDir("hdr_roundtrip");
  saveHdr(dir / "x.exr", img);
  const HdrImage loaded = loadHdr(dir / "x.exr");
  EXPECT_EQ(cv::norm(loaded.pixels, img, cv::NORM_INF), 0.0);
  saveHdr(dir / "x.hdr", img);
  const HdrImage rgbe = loadHdr(dir / "x.hdr");
  EXPECT_LT(cv::norm(rgbe.pixels, img, cv::NORM_INF) / 2.5e5, 0.01);  // RGBE keeps ~1% precision
}

TEST(HdrIo, MissingAndWrongFilesNameTheFile) {
  try {
    loadHdr("/nonexistent/pano.hdr");
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/pano.hdr"), std::string::npos);
  }
  const auto dir = test::scratchDir("hdr_wrong");
  {
    std::ofstream(dir / "garbage.exr") << "not an exr";
    EXPECT_THROW(loadHdr(dir / "garbage.exr"), InputError);
    std::ofstream(dir / "pano.png") << "x";
    EXPECT_THROW(loadHdr(dir / "pano.png"), InputError);
  }
}

class RealPanorama : public ::testing::TestWithParam<const char*> {};

TEST_P(RealPanorama, LoadsFiniteAndNonNegative) {
  const std::string rel = std::string("hdri/") + GetParam();
  HOLO_REQUIRE_SHARED_DATA(rel);
  const HdrImage hdr = loadHdr(test::sharedData(rel));
  EXPECT_GT(hdr.pixels.cols, 0);
  EXPECT_EQ(hdr.pixels.type(), CV_32FC3);
  double lo = 0, hi = 0;
  cv::minMaxLoc(hdr.pixels.reshape(1), &lo, &hi);
  EXPECT_GE(lo, 0.0);
  EXPECT_TRUE(std::isfinite(hi));
  EXPECT_GT(luminanceStats(hdr.pixels).mean, 0.0f);
}

INSTANTIATE_TEST_SUITE_P(SharedData, RealPanorama,
                         ::testing::Values("st_fagans_interior_1k.hdr", "empty_warehouse_01_1k.hdr",
                                           "lebombo_1k.hdr", "studio_small_03_1k.hdr", "rooitou_park_1k.hdr",
                                           "blender_studio_dwab.exr"));

TEST(HdrIo, HardSunPanoramaKeepsItsDynamicRange) {
  HOLO_REQUIRE_SHARED_DATA("hdri/rooitou_park_1k.hdr");
  const auto stats = luminanceStats(loadHdr(test::sharedData("hdri/rooitou_park_1k.hdr")).pixels);
  EXPECT_GT(stats.max, 1e4f);
  EXPECT_GT(stats.max / stats.mean, 1e3f);
}

TEST(HdrIo, DwabExrHasItsNegativePixelsCounted) {
  HOLO_REQUIRE_SHARED_DATA("hdri/blender_studio_dwab.exr");
  const HdrImage hdr = loadHdr(test::sharedData("hdri/blender_studio_dwab.exr"));
  EXPECT_GT(hdr.repaired.negative, 0);
  EXPECT_EQ(hdr.repaired.nan, 0);
}

}  // namespace
}  // namespace holo
