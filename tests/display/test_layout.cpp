// Layout math (no OpenGL): where the corners of each face's image land on the outputs.
#include <gtest/gtest.h>

#include <cmath>

#include "holo/core/error.hpp"
#include "holo/display/layout.hpp"

namespace holo::display {
namespace {

void expectNear(vec2 actual, vec2 expected, const char* what) {
  EXPECT_NEAR(actual.x, expected.x, 1e-3f) << what;
  EXPECT_NEAR(actual.y, expected.y, 1e-3f) << what;
}

DisplayConfig crossConfig(bool mirror) {
  DisplayConfig config;
  config.layout = LayoutKind::Cross;
  config.output_size = {384, 384};
  for (FaceSettings& face : config.faces) face.mirror = mirror;
  return config;
}

TEST(Layout, CrossViewsSurroundTheCentreAndTileTheScreen) {
  const DisplayConfig config = crossConfig(true);
  // view_size 1/3 and gap 1/6 of 384: 128-pixel squares touching the screen's edges.
  EXPECT_EQ(viewRect(config, 0, config.output_size), cv::Rect2f(128, 256, 128, 128));  // below
  EXPECT_EQ(viewRect(config, 1, config.output_size), cv::Rect2f(256, 128, 128, 128));  // right
  EXPECT_EQ(viewRect(config, 2, config.output_size), cv::Rect2f(128, 0, 128, 128));    // above
  EXPECT_EQ(viewRect(config, 3, config.output_size), cv::Rect2f(0, 128, 128, 128));    // left
}

// The image's top edge (v = 0) must point away from the centre on every face: farther from the
// centre is higher in the glass, so the relic stands upright for every viewer.
TEST(Layout, CrossImageTopPointsAwayFromTheCentre) {
  const DisplayConfig config = crossConfig(false);
  const vec2 centre(192.0f, 192.0f);
  for (int f = 0; f < kFaceCount; ++f) {
    const FacePlacement p = placeFace(config, f, config.output_size, {128.0f, 128.0f});
    const vec2 top_mid = p.apply({0.5f, 0.0f});
    const vec2 bottom_mid = p.apply({0.5f, 1.0f});
    EXPECT_GT(glm::length(top_mid - centre), glm::length(bottom_mid - centre)) << "face " << f;
  }
}

// Where the image's top-left corner goes with the default mirroring, worked out by hand from the
// pyramid: each viewer sees the face unmirrored in the glass.
TEST(Layout, CrossMirroredTopLeftCornerByHand) {
  const DisplayConfig config = crossConfig(true);
  const cv::Size crop(128, 128);
  expectNear(placeFace(config, 0, config.output_size, crop).apply({0, 0}), {128, 384}, "face 0: bottom-left");
  expectNear(placeFace(config, 1, config.output_size, crop).apply({0, 0}), {384, 256},
             "face 1: bottom-right");
  expectNear(placeFace(config, 2, config.output_size, crop).apply({0, 0}), {256, 0}, "face 2: top-right");
  expectNear(placeFace(config, 3, config.output_size, crop).apply({0, 0}), {0, 128}, "face 3: top-left");
}

TEST(Layout, MonitorsFitKeepsAspectAndCentres) {
  DisplayConfig config;
  config.layout = LayoutKind::Monitors;
  config.output_size = {200, 100};
  config.faces[1].mirror = false;
  const FacePlacement p = placeFace(config, 1, config.output_size, {50.0f, 100.0f});
  EXPECT_EQ(p.output, 1);
  expectNear(p.apply({0, 0}), {75, 0}, "top-left");
  expectNear(p.apply({1, 1}), {125, 100}, "bottom-right");
  EXPECT_EQ(canvasSize(config), cv::Size(400, 200));
  EXPECT_EQ(outputOrigin(config, 3), cv::Point(200, 100));
}

TEST(Layout, OffsetScaleAndExtraRotationComposeInTheViewFrame) {
  DisplayConfig config = crossConfig(false);
  FaceSettings& face = config.faces[2];  // above the centre, layout rotation 0
  face.scale = 0.5f;
  face.offset = {0.25f, 0.25f};  // right and up by a quarter of the view's side (32 px)
  face.rotation_deg = 90.0f;
  const FacePlacement p = placeFace(config, 2, config.output_size, {128.0f, 128.0f});
  // The offset (right 32, up 32) is (32, -32) on screen before the turn; turned clockwise by 90
  // degrees, (x, y) -> (-y, x), it is (32, 32): the view's centre (192, 64) moves to (224, 96).
  expectNear(p.apply({0.5f, 0.5f}), {224, 96}, "centre");
  // Image top-left goes to the top-right corner of the 64-pixel quad after the turn.
  expectNear(p.apply({0, 0}), {256, 64}, "top-left");
}

TEST(Layout, ArbitraryRotationFitsTheRotatedBoxInsideTheView) {
  DisplayConfig config = crossConfig(true);
  config.faces[1].rotation_deg = 30.0f;
  const FacePlacement p = placeFace(config, 1, config.output_size, {160.0f, 90.0f});
  for (const vec2 c : p.corners()) {
    EXPECT_GE(c.x, p.view.x - 1e-3f);
    EXPECT_LE(c.x, p.view.x + p.view.width + 1e-3f);
    EXPECT_GE(c.y, p.view.y - 1e-3f);
    EXPECT_LE(c.y, p.view.y + p.view.height + 1e-3f);
  }
}

// The face size the loop renders at follows the screen: what a face covers on it, no more.
TEST(Layout, FaceViewPixelsAreWhatTheScreenShowsAFaceAt) {
  DisplayConfig config;  // cross on a Full HD screen: a third of its 1080 rows per face
  EXPECT_EQ(faceViewPixels(config, {1920, 1080}), 360);
  EXPECT_EQ(faceViewPixels(config, {3840, 2160}), 720);
  config.layout = LayoutKind::Monitors;  // a whole monitor per face: its shorter side
  EXPECT_EQ(faceViewPixels(config, {1920, 1080}), 1080);
  config.layout = LayoutKind::Cross;
  config.faces[2].scale = 1.5f;  // the largest face decides, so none is shown upscaled
  EXPECT_EQ(faceViewPixels(config, {1920, 1080}), 540);
  config.faces[2].scale = 1.0f;
  config.faces[1].rotation_deg = 45.0f;  // a tilted face is fitted smaller: the others decide
  EXPECT_EQ(faceViewPixels(config, {1920, 1080}), 360);
  for (FaceSettings& face : config.faces) face.rotation_deg = 45.0f;
  EXPECT_EQ(faceViewPixels(config, {1920, 1080}), static_cast<int>(std::lround(360.0 / std::sqrt(2.0))));
}

TEST(Layout, EmptyCropIsAnError) {
  const DisplayConfig config = crossConfig(true);
  EXPECT_THROW(placeFace(config, 0, config.output_size, {0.0f, 10.0f}), Error);
  EXPECT_THROW(placeFace(config, 4, config.output_size, {10.0f, 10.0f}), Error);
}

}  // namespace
}  // namespace holo::display
