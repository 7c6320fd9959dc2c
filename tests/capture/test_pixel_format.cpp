// Conversions checked on byte layouts built by hand, as cameras put them on the wire.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "holo/capture/pixel_format.hpp"
#include "holo/core/error.hpp"

using namespace holo;
using namespace holo::capture;

namespace {
RawImage raw(const std::vector<std::uint8_t>& bytes, int w, int h) {
  return {bytes.data(), bytes.size(), w, h, 0};
}
}  // namespace

TEST(PixelFormat, NamesRoundTripAndUnknownNamesListTheChoices) {
  for (const auto& n : pixelFormatNames()) EXPECT_EQ(toString(pixelFormatFromName(n)), n);
  try {
    pixelFormatFromName("Mono12p");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("BayerRG8"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Mono12p"), std::string::npos) << e.what();
  }
}

TEST(PixelFormat, YuyvUsesY0UY1VOrder) {
  // Two pixels sharing U and V: Y0 = black (16), Y1 = white (235), neutral chroma.
  std::vector<std::uint8_t> grey{16, 128, 235, 128};
  const cv::Mat out = convertToColour(PixelFormat::YUYV, raw(grey, 2, 1));
  ASSERT_EQ(out.type(), CV_8UC3);
  EXPECT_LE(out.at<cv::Vec3b>(0, 0)[1], 2);
  EXPECT_GE(out.at<cv::Vec3b>(0, 1)[1], 253);
  // BT.601 red: Y 81, U (Cb) 90, V (Cr) 240 -> R high, G and B low (BGR order in the Mat).
  std::vector<std::uint8_t> red{81, 90, 81, 240};
  const cv::Vec3b p = convertToColour(PixelFormat::YUYV, raw(red, 2, 1)).at<cv::Vec3b>(0, 0);
  EXPECT_GT(p[2], 230);
  EXPECT_LT(p[1], 30);
  EXPECT_LT(p[0], 30);
}

TEST(PixelFormat, MjpegDecodesAndRejectsTruncatedOrMisSizedImages) {
  cv::Mat image(48, 64, CV_8UC3);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) image.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(x * 4), uchar(y * 5), 200);
  std::vector<std::uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95}));
  const cv::Mat out = convertToColour(PixelFormat::MJPEG, raw(jpeg, 64, 48));
  cv::Mat diff;
  cv::absdiff(out, image, diff);
  EXPECT_LT(cv::mean(diff)[0], 3.0);
  EXPECT_LT(cv::mean(diff)[2], 3.0);
  EXPECT_THROW(convertToColour(PixelFormat::MJPEG, raw(jpeg, 640, 480)), Error);
  std::vector<std::uint8_t> cut(jpeg.begin(), jpeg.begin() + 20);
  EXPECT_THROW(convertToColour(PixelFormat::MJPEG, raw(cut, 64, 48)), Error);
}

TEST(PixelFormat, Z16IsLittleEndianTimesMetresPerUnit) {
  // Three pixels: 1234 units, 0 (invalid), 65535 units.
  std::vector<std::uint8_t> bytes{0xD2, 0x04, 0x00, 0x00, 0xFF, 0xFF};
  const cv::Mat d = convertToDepth(PixelFormat::Z16, raw(bytes, 3, 1), 0.001);
  ASSERT_EQ(d.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(d.at<float>(0, 0), 1.234f);
  EXPECT_FLOAT_EQ(d.at<float>(0, 1), 0.0f);
  EXPECT_FLOAT_EQ(d.at<float>(0, 2), 65.535f);
  const cv::Mat c16 = convertToDepth(PixelFormat::Coord3D_C16, raw(bytes, 3, 1), 0.0002);
  EXPECT_FLOAT_EQ(c16.at<float>(0, 0), 1234.0f * 0.0002f);
  EXPECT_THROW(convertToDepth(PixelFormat::Z16, raw(bytes, 4, 1), 0.001), Error);  // too short
  EXPECT_THROW(convertToDepth(PixelFormat::RGB8, raw(bytes, 1, 1), 0.001), Error);
}

TEST(PixelFormat, MonoAndRgbLayouts) {
  std::vector<std::uint8_t> mono{7, 200};
  const cv::Mat m = convertToColour(PixelFormat::Mono8, raw(mono, 2, 1));
  EXPECT_EQ(m.at<cv::Vec3b>(0, 1), cv::Vec3b(200, 200, 200));
  std::vector<std::uint8_t> mono16{0xCD, 0xAB};  // 0xABCD little-endian = 43981 -> 43981 / 256 = 171.8 -> 172
  EXPECT_EQ(convertToColour(PixelFormat::Mono16, raw(mono16, 1, 1)).at<cv::Vec3b>(0, 0)[0], 172);
  std::vector<std::uint8_t> rgb{10, 20, 30};
  EXPECT_EQ(convertToColour(PixelFormat::RGB8, raw(rgb, 1, 1)).at<cv::Vec3b>(0, 0), cv::Vec3b(30, 20, 10));
  // Row stride larger than the row: padding bytes are skipped.
  std::vector<std::uint8_t> padded{1, 2, 99, 99, 3, 4, 99, 99};
  const cv::Mat s = convertToColour(PixelFormat::Mono8, {padded.data(), padded.size(), 2, 2, 4});
  EXPECT_EQ(s.at<cv::Vec3b>(1, 0)[0], 3);
}

// Each Bayer mosaic built from one known colour must demosaic back to it: pins down the
// PFNC-versus-OpenCV naming of the four patterns.
TEST(PixelFormat, BayerPatternsDemosaicToTheColourTheyWereBuiltFrom) {
  const int b = 30, g = 100, r = 220;
  struct Case {
    PixelFormat format;
    int first_row[2];  // channel at (0,0), (0,1): 0 = B, 1 = G, 2 = R
    int second_row[2];
  };
  const Case cases[] = {{PixelFormat::BayerRG8, {2, 1}, {1, 0}},
                        {PixelFormat::BayerGR8, {1, 2}, {0, 1}},
                        {PixelFormat::BayerGB8, {1, 0}, {2, 1}},
                        {PixelFormat::BayerBG8, {0, 1}, {1, 2}}};
  const int value[3] = {b, g, r};
  for (const Case& c : cases) {
    std::vector<std::uint8_t> mosaic(16 * 16);
    for (int y = 0; y < 16; ++y) {
      // The row is picked before it is indexed: GCC 12 with -fsanitize=undefined miscompiles
      // `(cond ? a.first : a.second)[x % 2]` (the instrumented index is computed only in the
      // first arm, the second reads an unset temporary), which built a wrong mosaic under ASan.
      const int* row = y % 2 == 0 ? c.first_row : c.second_row;
      for (int x = 0; x < 16; ++x)
        mosaic[static_cast<std::size_t>(y * 16 + x)] = static_cast<std::uint8_t>(value[row[x % 2]]);
    }
    ASSERT_EQ(mosaic[17], value[c.second_row[1]]) << toString(c.format);  // the mosaic is as built
    const cv::Vec3b p = convertToColour(c.format, raw(mosaic, 16, 16)).at<cv::Vec3b>(8, 8);
    EXPECT_NEAR(p[0], b, 2) << toString(c.format);
    EXPECT_NEAR(p[1], g, 2) << toString(c.format);
    EXPECT_NEAR(p[2], r, 2) << toString(c.format);
  }
}

TEST(PixelFormat, ShortBuffersAreRejectedWithSizes) {
  std::vector<std::uint8_t> bytes(10);
  try {
    convertToColour(PixelFormat::RGB8, raw(bytes, 4, 4));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("expected at least 48"), std::string::npos) << e.what();
  }
}

// A camera announcing 64k x 64k is refused by its size alone, in every format, before any
// conversion allocates for it; the message says the limit.
TEST(PixelFormat, ACameraAnnouncing64kBy64kIsRefusedWithTheLimit) {
  std::vector<std::uint8_t> bytes(64);
  for (const std::string& name : pixelFormatNames()) {
    const PixelFormat format = pixelFormatFromName(name);
    try {
      if (isDepthFormat(format))
        convertToDepth(format, raw(bytes, 65536, 65536), 0.001);
      else
        convertToColour(format, raw(bytes, 65536, 65536));
      ADD_FAILURE() << name << " converted a 65536x65536 frame";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxFrameSide)), std::string::npos)
          << name << ": " << e.what();
    }
  }
  try {
    checkFrameSize("aravis camera GV-1", "width/height", 65536, 65536);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "aravis camera GV-1");
    EXPECT_NE(std::string(e.what()).find("65536x65536"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(checkFrameSize("cam", "width/height", kMaxFrameSide, kMaxFrameSide));
  EXPECT_THROW(checkFrameSize("cam", "width/height", 0, 480), InputError);
}

// A 16-bit buffer whose stride is not a whole number of samples is a failed frame (holo::Error),
// not an OpenCV assertion escaping the capture thread.
TEST(PixelFormat, OddStrideOfASixteenBitFormatIsAFailedFrame) {
  std::vector<std::uint8_t> bytes(64);
  RawImage image = raw(bytes, 4, 4);
  image.stride = 9;
  EXPECT_THROW(convertToDepth(PixelFormat::Z16, image, 0.001), Error);
  EXPECT_THROW(convertToColour(PixelFormat::Mono16, image), Error);
}
