// The quad view through OpenGL 3.3 core, read back and compared with the CPU reference
// (cpu_compose.hpp) and with positions worked out by hand. Headless tests use EGL on Mesa's
// surfaceless platform (llvmpipe on the CPU); they skip only when no EGL context can be made.
// QuadViewWindow.* needs an X display (ctest runs it under xvfb-run).
#include <gtest/gtest.h>

#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "holo/core/error.hpp"
#include "holo/display/cpu_compose.hpp"
#include "holo/display/quad_view_presenter.hpp"
#include "holo/display/test_pattern.hpp"
#include "shared_data.hpp"

namespace holo::display {
namespace {

std::unique_ptr<QuadViewPresenter> headlessOrSkip(const DisplayConfig& config, std::string& why) {
  try {
    return makeHeadlessPresenter(config);
  } catch (const Error& e) {
    why = e.what();
    return nullptr;
  }
}

#define HEADLESS_OR_SKIP(presenter, config)             \
  std::string skip_reason;                              \
  auto presenter = headlessOrSkip(config, skip_reason); \
  if (!presenter) GTEST_SKIP() << "EGL cannot be initialised: " << skip_reason

// Output sizes chosen so that, with 128x128 faces, every quad edge lies on whole pixels: the
// cross views are 128-pixel squares; a monitor output of 160x128 holds a 128x128 face.
DisplayConfig baseConfig(LayoutKind kind) {
  DisplayConfig config;
  config.layout = kind;
  config.output_size = kind == LayoutKind::Cross ? cv::Size(384, 384) : cv::Size(160, 128);
  return config;
}

FaceImages patternFaces(int side = 128) {
  FaceImages faces;
  for (int f = 0; f < kFaceCount; ++f) faces[static_cast<std::size_t>(f)] = testPatternFace(f, {side, side});
  return faces;
}

double maxDifference(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a, b, cv::NORM_INF);
}

// Presents `faces`, reads the canvas back and checks it against the CPU reference: within 1 LSB
// everywhere and exactly black wherever no face covers a pixel.
void expectMatchesReference(const DisplayConfig& config, const FaceImages& faces, const std::string& what) {
  std::string why;
  auto presenter = headlessOrSkip(config, why);
  ASSERT_TRUE(presenter) << why;
  presenter->present(faces);
  const cv::Mat gpu = presenter->readBack();
  const cv::Mat cpu = composeCanvasCpu(config, faces, presenter->lastCrops());
  ASSERT_EQ(gpu.size(), canvasSize(config)) << what;
  EXPECT_LE(maxDifference(gpu, cpu), 1.0) << what;
  const cv::Mat covered = coverageCpu(config, faces, presenter->lastCrops());
  cv::Mat background;
  gpu.copyTo(background, ~covered);
  EXPECT_EQ(cv::countNonZero(background.reshape(1)), 0) << what << ": background not black";
  EXPECT_GT(cv::countNonZero(covered), 0) << what;
}

struct LayoutCase {
  LayoutKind kind;
  bool mirror;
  float rotation_deg;
};

class QuadViewGl : public ::testing::TestWithParam<LayoutCase> {};

TEST_P(QuadViewGl, MatchesCpuReference) {
  const LayoutCase& c = GetParam();
  {
    std::string why;
    if (!headlessOrSkip(baseConfig(c.kind), why)) GTEST_SKIP() << "EGL cannot be initialised: " << why;
  }
  DisplayConfig config = baseConfig(c.kind);
  for (FaceSettings& face : config.faces) {
    face.mirror = c.mirror;
    face.rotation_deg = c.rotation_deg;
  }
  expectMatchesReference(config, patternFaces(), "plain");

  // Half size (bilinear weights 1/2) moved by whole pixels: offsets of 1/4 and -1/8 of 128.
  for (int f = 0; f < kFaceCount; ++f) {
    FaceSettings& face = config.faces[static_cast<std::size_t>(f)];
    face.scale = 0.5f;
    face.offset = vec2(f % 2 ? 0.25f : -0.125f, f / 2 ? -0.125f : 0.25f);
  }
  expectMatchesReference(config, patternFaces(), "scale 0.5 with offsets");

  // Double size (weights 1/4, 3/4); the cross views overlap, later faces on top.
  for (FaceSettings& face : config.faces) {
    face.scale = 2.0f;
    face.offset = vec2(0.0f);
  }
  expectMatchesReference(config, patternFaces(64), "scale 2 of 64-pixel faces");
}

std::string caseName(const ::testing::TestParamInfo<LayoutCase>& info) {
  return std::string(layoutName(info.param.kind)) + (info.param.mirror ? "_mirrored_" : "_plain_") +
         std::to_string(static_cast<int>(info.param.rotation_deg));
}

std::vector<LayoutCase> allCases() {
  std::vector<LayoutCase> cases;
  for (LayoutKind kind : {LayoutKind::Monitors, LayoutKind::Cross})
    for (bool mirror : {false, true})
      for (float rotation : {0.0f, 90.0f, 180.0f, 270.0f}) cases.push_back({kind, mirror, rotation});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Layouts, QuadViewGl, ::testing::ValuesIn(allCases()), caseName);

// A 16x16 marker in the top-left corner of each face, in the face's colour.
FaceImages markerFaces() {
  FaceImages faces;
  for (int f = 0; f < kFaceCount; ++f) {
    cv::Mat face(128, 128, CV_8UC3, cv::Scalar::all(0));
    const cv::Vec3b colour = patternColour(f);
    face(cv::Rect(0, 0, 16, 16)).setTo(cv::Scalar(colour[0], colour[1], colour[2]));
    faces[static_cast<std::size_t>(f)] = face;
  }
  return faces;
}

// Centre of the pixels of exactly `colour`; (-1, -1) when there are none.
cv::Point2d centroidOf(const cv::Mat& image, cv::Vec3b colour) {
  cv::Mat mask;
  cv::inRange(image, cv::Scalar(colour[0], colour[1], colour[2]), cv::Scalar(colour[0], colour[1], colour[2]),
              mask);
  const cv::Moments m = cv::moments(mask, true);
  if (m.m00 == 0.0) return {-1.0, -1.0};
  return {m.m10 / m.m00 + 0.5, m.m01 / m.m00 + 0.5};  // pixel centres at k + 0.5
}

// Read back through EGL, the marker lands where the pyramid needs it (worked out by hand in
// test_layout.cpp's CrossMirroredTopLeftCornerByHand), 8 pixels in from the view's corner.
TEST(QuadViewGlOrientation, CrossMarkersLandInTheHandWorkedCorners) {
  const DisplayConfig config = baseConfig(LayoutKind::Cross);
  HEADLESS_OR_SKIP(presenter, config);
  presenter->present(markerFaces());
  const cv::Mat canvas = presenter->readBack();
  const cv::Point2d expected[kFaceCount] = {{136, 376}, {376, 248}, {248, 8}, {8, 136}};
  for (int f = 0; f < kFaceCount; ++f) {
    const cv::Point2d c = centroidOf(canvas, patternColour(f));
    EXPECT_NEAR(c.x, expected[f].x, 0.5) << "face " << f;
    EXPECT_NEAR(c.y, expected[f].y, 0.5) << "face " << f;
    EXPECT_EQ(cv::countNonZero(cv::Mat(canvas == cv::Scalar(0, 0, 0, 0)).reshape(1)) > 0, true);
  }
}

TEST(QuadViewGlOrientation, MonitorMarkersLandTopRightOfEachOutputWhenMirrored) {
  const DisplayConfig config = baseConfig(LayoutKind::Monitors);
  HEADLESS_OR_SKIP(presenter, config);
  presenter->present(markerFaces());
  const cv::Mat canvas = presenter->readBack();
  for (int f = 0; f < kFaceCount; ++f) {
    const cv::Point origin = outputOrigin(config, f);
    const cv::Point2d c = centroidOf(canvas, patternColour(f));
    // The 128-pixel face spans x 16..144 of its 160x128 output; mirrored, its top-left is at the
    // top-right.
    EXPECT_NEAR(c.x, origin.x + 136.0, 0.5) << "face " << f;
    EXPECT_NEAR(c.y, origin.y + 8.0, 0.5) << "face " << f;
  }
}

TEST(QuadViewGlPresent, BackgroundIsExactlyBlackAroundWhiteFaces) {
  DisplayConfig config = baseConfig(LayoutKind::Cross);
  for (FaceSettings& face : config.faces) face.scale = 0.75f;
  HEADLESS_OR_SKIP(presenter, config);
  FaceImages faces;
  for (cv::Mat& face : faces) face = cv::Mat(128, 128, CV_8UC3, cv::Scalar::all(255));
  presenter->present(faces);
  const cv::Mat canvas = presenter->readBack();
  cv::Mat grey;
  cv::cvtColor(canvas, grey, cv::COLOR_BGR2GRAY);
  // Each face covers a 96x96 square; the rest of the 384x384 screen stays 0 exactly.
  EXPECT_EQ(cv::countNonZero(grey == 255), 4 * 96 * 96);
  EXPECT_EQ(cv::countNonZero(grey), 4 * 96 * 96);
}

TEST(QuadViewGlPresent, MissingFaceKeepsItsLastImage) {
  const DisplayConfig config = baseConfig(LayoutKind::Cross);
  HEADLESS_OR_SKIP(presenter, config);
  FaceImages faces = patternFaces();
  presenter->present(faces);
  const cv::Mat full = presenter->readBack();
  faces[1] = cv::Mat();
  presenter->present(faces);
  EXPECT_EQ(maxDifference(presenter->readBack(), full), 0.0) << "face 1 went black";
  presenter->present(FaceImages{});
  EXPECT_EQ(maxDifference(presenter->readBack(), full), 0.0) << "all faces missing";
  // A new image for face 2 replaces only face 2.
  faces = FaceImages{};
  faces[2] = cv::Mat(128, 128, CV_8UC3, cv::Scalar::all(255));
  presenter->present(faces);
  const cv::Mat after = presenter->readBack();
  const cv::Rect view2 = viewRect(config, 2, config.output_size);
  EXPECT_EQ(cv::countNonZero(cv::Mat(after(view2) != 255).reshape(1)), 0);
  const cv::Rect view0 = viewRect(config, 0, config.output_size);
  EXPECT_EQ(maxDifference(after(view0), full(view0)), 0.0);
}

TEST(QuadViewGlPresent, NeverPresentedFaceStaysBlack) {
  const DisplayConfig config = baseConfig(LayoutKind::Cross);
  HEADLESS_OR_SKIP(presenter, config);
  EXPECT_EQ(cv::countNonZero(presenter->readBack().reshape(1)), 0) << "black before the first frame";
  FaceImages faces;
  faces[0] = testPatternFace(0, {128, 128});
  presenter->present(faces);
  const cv::Mat canvas = presenter->readBack();
  for (int f = 1; f < kFaceCount; ++f)
    EXPECT_EQ(cv::countNonZero(canvas(viewRect(config, f, config.output_size)).clone().reshape(1)), 0);
}

TEST(QuadViewGlPresent, LinearHdrFacesMatchTheCpuEncodingAndNanIsBlack) {
  DisplayConfig config = baseConfig(LayoutKind::Cross);
  config.exposure = 0.5f;
  FaceImages faces;
  for (int f = 0; f < kFaceCount; ++f) {
    cv::Mat face(128, 128, CV_32FC3);
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 128; ++x)
        face.at<cv::Vec3f>(y, x) = cv::Vec3f(x / 64.0f, y / 100.0f, static_cast<float>(f) * 0.3f + 1e-3f);
    faces[static_cast<std::size_t>(f)] = face;
  }
  expectMatchesReference(config, faces, "linear HDR");

  // NaN and +Inf texels: NaN shows black, +Inf saturates, nothing else changes.
  faces[2].at<cv::Vec3f>(64, 64) = cv::Vec3f(std::nanf(""), std::nanf(""), std::nanf(""));
  faces[2].at<cv::Vec3f>(10, 10) = cv::Vec3f(INFINITY, INFINITY, INFINITY);
  HEADLESS_OR_SKIP(presenter, config);
  presenter->present(faces);
  const cv::Mat canvas = presenter->readBack();
  const FacePlacement p = placeFace(config, 2, config.output_size, {128.0f, 128.0f});
  const vec2 nan_at = p.apply({64.5f / 128.0f, 64.5f / 128.0f});
  const vec2 inf_at = p.apply({10.5f / 128.0f, 10.5f / 128.0f});
  EXPECT_EQ(canvas.at<cv::Vec3b>(static_cast<int>(nan_at.y), static_cast<int>(nan_at.x)), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(canvas.at<cv::Vec3b>(static_cast<int>(inf_at.y), static_cast<int>(inf_at.x)),
            cv::Vec3b(255, 255, 255));
}

TEST(QuadViewGlPresent, WrongFaceTypeIsAnError) {
  const DisplayConfig config = baseConfig(LayoutKind::Cross);
  HEADLESS_OR_SKIP(presenter, config);
  FaceImages faces;
  faces[0] = cv::Mat(32, 32, CV_16UC3, cv::Scalar::all(0));
  EXPECT_THROW(presenter->present(faces), Error);
}

// Headless recording: every presented frame lands in the MP4, every second one as a PNG equal to
// the canvas read back through EGL.
TEST(QuadViewGlPresent, RecordingWritesMp4AndPngFrames) {
  const DisplayConfig config = baseConfig(LayoutKind::Cross);
  HEADLESS_OR_SKIP(headless, config);
  const auto dir = test::scratchDir("display_recording");
  RecordingSettings settings;
  settings.out_dir = dir;
  settings.fps = 10.0;
  settings.png_every = 2;
  auto recorder = makeRecordingPresenter(std::move(headless), settings);
  FaceImages faces = patternFaces();
  cv::Mat frame_two;
  for (int i = 0; i < 5; ++i) {
    faces[static_cast<std::size_t>(i % kFaceCount)] = cv::Mat();  // one face late each frame
    recorder->present(faces);
    if (i == 2) frame_two = recorder->readBack();
    faces = patternFaces();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "quadview.mp4")) << "the video appears at finish()";
  recorder->finish();
  cv::VideoCapture video((dir / "quadview.mp4").string(), cv::CAP_FFMPEG);
  ASSERT_TRUE(video.isOpened());
  EXPECT_EQ(static_cast<int>(video.get(cv::CAP_PROP_FRAME_COUNT)), 5);
  for (const char* name : {"frame_00000.png", "frame_00002.png", "frame_00004.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  EXPECT_FALSE(std::filesystem::exists(dir / "frame_00001.png"));
  const cv::Mat png = cv::imread((dir / "frame_00002.png").string(), cv::IMREAD_COLOR);
  EXPECT_EQ(maxDifference(png, frame_two), 0.0);
}

// The same quad view in GLFW windows (plain windows of output_size, as under Xvfb) reads back
// the same pixels as the headless EGL canvas.
TEST(QuadViewWindow, SameScreenshotAsHeadless) {
  if (!std::getenv("DISPLAY")) GTEST_SKIP() << "no X display; ctest runs this under xvfb-run";
  for (LayoutKind kind : {LayoutKind::Cross, LayoutKind::Monitors}) {
    DisplayConfig config = baseConfig(kind);
    config.fullscreen = false;
    const FaceImages faces = patternFaces();
    // Both alive in one thread: each presenter releases its context after every call.
    HEADLESS_OR_SKIP(headless, config);
    auto window = makeWindowPresenter(config);
    headless->present(faces);
    window->present(faces);
    EXPECT_TRUE(window->isOpen());
    const cv::Mat from_window = window->readBack();
    ASSERT_EQ(from_window.size(), canvasSize(config)) << layoutName(kind);
    EXPECT_LE(maxDifference(from_window, headless->readBack()), 1.0) << layoutName(kind);
  }
}

}  // namespace
}  // namespace holo::display
