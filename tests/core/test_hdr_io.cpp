#include <gtest/gtest.h>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <vector>

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

// Loading must fail with an InputError whose message holds every one of `needles`.
void expectRefused(const std::filesystem::path& path, std::initializer_list<std::string> needles) {
  try {
    loadHdr(path);
    ADD_FAILURE() << "loaded " << path;
  } catch (const InputError& e) {
    for (const auto& needle : needles)
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

// A 16k x 8k panorama is refused from its header: the files here are a few bytes, and the check
// comes before the 1.5 GiB of float pixels would be allocated.
TEST(HdrIo, SixteenKPanoramaIsRefusedFromItsHeader) {
  const auto dir = test::scratchDir("hdr_16k");
  std::ofstream(dir / "big.hdr", std::ios::binary)
      << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n"
      << std::string(64, '\x80');
  expectRefused(dir / "big.hdr", {"resolution", "16384x8192", std::to_string(kMaxPanoramaPixels)});

  // An EXR whose data window says 16384x8192: a real 4x2 file with its dataWindow patched.
  saveHdr(dir / "small.exr", cv::Mat(2, 4, CV_32FC3, cv::Scalar::all(1.0f)));
  std::ifstream in(dir / "small.exr", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string attribute("dataWindow\0box2i\0", 17);
  const auto at = bytes.find(attribute);
  ASSERT_NE(at, std::string::npos);
  const std::int32_t window[4] = {0, 0, 16383, 8191};  // xmin ymin xmax ymax, little-endian
  bytes.replace(at + attribute.size() + 4, sizeof window, reinterpret_cast<const char*>(window),
                sizeof window);
  // Room for the line offset table OpenEXR reads on opening (8 bytes per chunk of lines).
  std::ofstream(dir / "big.exr", std::ios::binary) << bytes << std::string(8192 * 8, '\0');
  expectRefused(dir / "big.exr", {"dataWindow", "16384x8192"});

  // An inverted window is no image at all.
  const std::int32_t inverted[4] = {5, 0, 0, 1};
  bytes.replace(at + attribute.size() + 4, sizeof inverted, reinterpret_cast<const char*>(inverted),
                sizeof inverted);
  std::ofstream(dir / "inverted.exr", std::ios::binary) << bytes;
  EXPECT_THROW(loadHdr(dir / "inverted.exr"), InputError);
}

// An EXR header attribute stating more bytes than the file holds is refused before OpenEXR reads
// it: OpenEXR 3.1 allocated a string attribute at its stated size first (1.7 GB for a damaged
// 3.6 KB file that fuzz_hdr found). Here a real 4x2 file gets a string attribute stating 1.6 GB.
TEST(HdrIo, AnExrAttributeLargerThanItsFileIsRefusedBeforeReading) {
  const auto dir = test::scratchDir("hdr_exr_attribute");
  saveHdr(dir / "small.exr", cv::Mat(2, 4, CV_32FC3, cv::Scalar::all(1.0f)));
  std::ifstream in(dir / "small.exr", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::int32_t huge = 0x63000000;
  bytes.insert(
      8, std::string("note\0string\0", 12) + std::string(reinterpret_cast<const char*>(&huge), 4) + "x");
  std::ofstream(dir / "bomb.exr", std::ios::binary) << bytes;
  try {
    loadHdr(dir / "bomb.exr");
    ADD_FAILURE() << "loaded an EXR stating a 1.6 GB attribute";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "header attribute 'note'") << e.what();
    EXPECT_NE(std::string(e.what()).find(std::to_string(huge) + " bytes"), std::string::npos) << e.what();
  }
  // The file itself, untouched, still loads.
  EXPECT_EQ(loadHdr(dir / "small.exr").pixels.cols, 4);
}

// A .hdr file is decoded only when it is a Radiance file: OpenCV picks decoders by content, so a
// PNG (or a JPEG 2000, as fuzz_hdr sent) named .hdr would otherwise reach other decoders.
TEST(HdrIo, OnlyRadianceContentIsDecodedAsHdr) {
  const auto dir = test::scratchDir("hdr_signature");
  std::vector<std::uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", cv::Mat(2, 4, CV_8UC3, cv::Scalar::all(200)), png));
  std::ofstream(dir / "png.hdr", std::ios::binary)
      .write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  expectRefused(dir / "png.hdr", {"#?RADIANCE", "another format"});
  saveHdr(dir / "real.hdr", cv::Mat(2, 4, CV_32FC3, cv::Scalar::all(0.5f)));
  EXPECT_EQ(loadHdr(dir / "real.hdr").pixels.cols, 4);
}

// The inputs fuzz_hdr once crashed, hung or exhausted memory with: each is an InputError now.
TEST(HdrIo, FuzzRegressionsAreInputErrors) {
  const auto dir = test::scratchDir("hdr_fuzz_regressions");
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(HOLO_SOURCE_DIR) /
                                                               "tests/fuzz/regressions/fuzz_hdr")) {
    std::ifstream file(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    const bool exr = bytes.rfind(std::string("\x76\x2f\x31\x01", 4), 0) == 0;  // as fuzz_hdr picks
    const auto copy = dir / (exr ? "input.exr" : "input.hdr");
    std::ofstream(copy, std::ios::binary) << bytes;
    EXPECT_THROW(loadHdr(copy), InputError) << entry.path();
    ++files;
  }
  EXPECT_GE(files, 1);
}

// At the limit a panorama's header passes: 8192x4096 is accepted up to its (here missing) pixels.
TEST(HdrIo, PanoramaAtTheLimitIsNotRefusedForItsSize) {
  const auto dir = test::scratchDir("hdr_8k");
  std::ofstream(dir / "limit.hdr", std::ios::binary)
      << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8192\n";
  try {
    loadHdr(dir / "limit.hdr");
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find("at most"), std::string::npos) << e.what();
  }
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
