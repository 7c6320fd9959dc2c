#include "holo/pipeline/calibrated_display.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "holo/capture/capture_config.hpp"
#include "holo/core/log.hpp"
#include "holo/display/display_config.hpp"

namespace holo::pipeline {

namespace {

// Into (-180, 180] degrees.
float wrapDegrees(float degrees) {
  float wrapped = std::fmod(degrees, 360.0f);
  if (wrapped <= -180.0f) wrapped += 360.0f;
  if (wrapped > 180.0f) wrapped -= 360.0f;
  return wrapped;
}

}  // namespace

display::FaceSettings faceSettingsFromCalibration(const calib::FaceAlignment& alignment,
                                                  const calib::PyramidCalibration& pyramid,
                                                  display::LayoutKind layout, int face) {
  display::FaceSettings settings;
  settings.mirror = alignment.mirror;
  // The display fits the (square) face's turned bounding box into its view, shrinking a tilted
  // face by |cos| + |sin|; the calibration measured the face's own size: undo the shrink.
  const float turn = alignment.rotation_deg * kPi / 180.0f;
  settings.scale = alignment.scale * (std::abs(std::cos(turn)) + std::abs(std::sin(turn)));
  // Counter-clockwise t is clockwise -t; the layout already turns the face by its own angle.
  const float clockwise = -alignment.rotation_deg;
  settings.rotation_deg = wrapDegrees(clockwise - display::layoutRotationDeg(layout, face));
  // The screen offset is the view-frame offset turned clockwise with the face: turn it back.
  const float radians = clockwise * kPi / 180.0f;
  const float c = std::cos(radians), s = std::sin(radians);
  const vec2 screen = alignment.offset_px;
  const vec2 view(c * screen.x + s * screen.y, -s * screen.x + c * screen.y);
  const float side = static_cast<float>(std::min(pyramid.face_view_width, pyramid.face_view_height));
  settings.offset = vec2(view.x / side, -view.y / side);
  return settings;
}

display::DisplayConfig applyCalibratedFaces(display::DisplayConfig config, const ConfigNode& root,
                                            const calib::PyramidCalibration& pyramid) {
  std::optional<ConfigNode> faces;
  if (const auto section = root.find("display")) faces = section->find("faces");
  for (int f = 0; f < display::kFaceCount; ++f) {
    const display::FaceSettings calibrated =
        faceSettingsFromCalibration(pyramid.faces[static_cast<std::size_t>(f)], pyramid, config.layout, f);
    display::FaceSettings& face = config.faces[static_cast<std::size_t>(f)];
    const auto given = [&](const char* key) {
      return faces && faces->isSequence() && (*faces)[static_cast<std::size_t>(f)].has(key);
    };
    if (!given("mirror")) face.mirror = calibrated.mirror;
    if (!given("offset")) face.offset = calibrated.offset;
    if (!given("scale")) face.scale = calibrated.scale;
    if (!given("rotation")) face.rotation_deg = calibrated.rotation_deg;
  }
  return config;
}

display::DisplayConfig calibratedDisplayConfig(const ConfigNode& root,
                                               std::optional<display::LayoutKind> layout) {
  display::DisplayConfig config = display::displayConfigOf(root);
  if (layout) config.layout = *layout;
  if (!root.isMap() || !root.has("capture")) return config;
  const capture::CaptureConfig capture = capture::parseCaptureConfig(root["capture"]);
  const std::filesystem::path pyramid = calib::pyramidCalibrationPath(capture.calibration_dir);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(pyramid, ec)) {
    HOLO_LOG_WARN("{}: no pyramid calibration, the faces are laid out as the display section says",
                  pyramid.string());
    return config;
  }
  HOLO_LOG_INFO("face alignment from {} (display.faces overrides the fields it sets)", pyramid.string());
  return applyCalibratedFaces(std::move(config), root, calib::loadPyramidCalibration(pyramid));
}

}  // namespace holo::pipeline
