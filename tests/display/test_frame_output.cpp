// PNG and MP4 output: written atomically, read back with OpenCV.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "holo/core/error.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/display/test_pattern.hpp"
#include "shared_data.hpp"

namespace holo::display {
namespace {

TEST(FrameOutput, PngRoundTripIsLossless) {
  const auto dir = test::scratchDir("display_png");
  const cv::Mat pattern = testPatternFace(1, {96, 64});
  writePngAtomically(dir / "face.png", pattern);
  const cv::Mat back = cv::imread((dir / "face.png").string(), cv::IMREAD_COLOR);
  ASSERT_EQ(back.size(), pattern.size());
  EXPECT_EQ(cv::norm(back, pattern, cv::NORM_INF), 0.0);
}

TEST(FrameOutput, Mp4RoundTripKeepsFrameCountAndColours) {
  const auto dir = test::scratchDir("display_mp4");
  const auto path = dir / "quad.mp4";
  constexpr int kFrames = 12;
  std::string fourcc;
  {
    VideoFileWriter writer(path, {128, 96}, 25.0);
    fourcc = writer.fourcc();
    for (int i = 0; i < kFrames; ++i) {
      cv::Mat frame(96, 128, CV_8UC3, cv::Scalar::all(0));
      frame(cv::Rect(0, 0, 64, 96)).setTo(cv::Scalar(0, 0, 200));   // red left half
      frame(cv::Rect(64, 0, 64, 96)).setTo(cv::Scalar(200, 0, 0));  // blue right half
      writer.write(frame);
    }
    EXPECT_FALSE(std::filesystem::exists(path)) << "the final file appears only at finish()";
    writer.finish();
    EXPECT_EQ(writer.framesWritten(), kFrames);
  }
  ASSERT_TRUE(std::filesystem::exists(path));
  cv::VideoCapture capture(path.string(), cv::CAP_FFMPEG);
  ASSERT_TRUE(capture.isOpened()) << fourcc;
  EXPECT_EQ(static_cast<int>(capture.get(cv::CAP_PROP_FRAME_COUNT)), kFrames) << fourcc;
  int decoded = 0;
  cv::Mat frame;
  while (capture.read(frame)) {
    ASSERT_EQ(frame.size(), cv::Size(128, 96));
    // Lossy codec: the halves keep their colour within a few levels away from the seam.
    const cv::Scalar left = cv::mean(frame(cv::Rect(8, 8, 48, 80)));
    const cv::Scalar right = cv::mean(frame(cv::Rect(72, 8, 48, 80)));
    EXPECT_NEAR(left[2], 200.0, 12.0);
    EXPECT_NEAR(left[0], 0.0, 12.0);
    EXPECT_NEAR(right[0], 200.0, 12.0);
    EXPECT_NEAR(right[2], 0.0, 12.0);
    ++decoded;
  }
  EXPECT_EQ(decoded, kFrames);
}

TEST(FrameOutput, UnfinishedVideoLeavesNoFile) {
  const auto dir = test::scratchDir("display_mp4_abandoned");
  {
    VideoFileWriter writer(dir / "abandoned.mp4", {64, 64}, 25.0);
    writer.write(cv::Mat(64, 64, CV_8UC3, cv::Scalar::all(50)));
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(FrameOutput, WrongFrameSizeIsAnError) {
  const auto dir = test::scratchDir("display_mp4_wrong");
  VideoFileWriter writer(dir / "wrong.mp4", {64, 64}, 25.0);
  EXPECT_THROW(writer.write(cv::Mat(32, 64, CV_8UC3)), Error);
  EXPECT_THROW(writer.write(cv::Mat(64, 64, CV_32FC3)), Error);
}

}  // namespace
}  // namespace holo::display
