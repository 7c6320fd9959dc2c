#include "holo/display/layout.hpp"

#include <algorithm>
#include <cmath>

#include "holo/core/error.hpp"

namespace holo::display {

namespace {

// cos and sin of a clockwise angle in degrees, exact at multiples of 90 degrees so that the
// usual layouts land on whole pixels.
vec2 cosSinDeg(float degrees) {
  const double wrapped = std::fmod(std::fmod(static_cast<double>(degrees), 360.0) + 360.0, 360.0);
  if (wrapped == 0.0) return {1.0f, 0.0f};
  if (wrapped == 90.0) return {0.0f, 1.0f};
  if (wrapped == 180.0) return {-1.0f, 0.0f};
  if (wrapped == 270.0) return {0.0f, -1.0f};
  const double radians = wrapped * static_cast<double>(kPi) / 180.0;
  return {static_cast<float>(std::cos(radians)), static_cast<float>(std::sin(radians))};
}

mat3 translation(vec2 t) {
  mat3 m(1.0f);
  m[2] = vec3(t, 1.0f);
  return m;
}

mat3 scaling(vec2 s) {
  mat3 m(1.0f);
  m[0][0] = s.x;
  m[1][1] = s.y;
  return m;
}

// Clockwise on screen with +y down: x' = x cos - y sin, y' = x sin + y cos.
mat3 rotation(vec2 cs) {
  mat3 m(1.0f);
  m[0] = vec3(cs.x, cs.y, 0.0f);
  m[1] = vec3(-cs.y, cs.x, 0.0f);
  return m;
}

void checkFace(int face) {
  if (face < 0 || face >= kFaceCount)
    throw Error("display: face index " + std::to_string(face) + " outside 0..3");
}

}  // namespace

const char* layoutName(LayoutKind kind) {
  return kind == LayoutKind::Monitors ? "monitors" : "cross";
}

int outputCount(LayoutKind kind) {
  return kind == LayoutKind::Monitors ? kFaceCount : 1;
}

vec2 FacePlacement::apply(vec2 unit) const {
  return vec2(unit_to_output * vec3(unit, 1.0f));
}

std::array<vec2, 4> FacePlacement::corners() const {
  return {apply({0.0f, 0.0f}), apply({1.0f, 0.0f}), apply({1.0f, 1.0f}), apply({0.0f, 1.0f})};
}

float layoutRotationDeg(LayoutKind kind, int face) {
  checkFace(face);
  if (kind == LayoutKind::Monitors) return 0.0f;
  static constexpr float kCross[kFaceCount] = {180.0f, 90.0f, 0.0f, 270.0f};
  return kCross[face];
}

cv::Rect2f viewRect(const DisplayConfig& config, int face, cv::Size output) {
  checkFace(face);
  const float w = static_cast<float>(output.width);
  const float h = static_cast<float>(output.height);
  if (config.layout == LayoutKind::Monitors) return {0.0f, 0.0f, w, h};
  const float shorter = std::min(w, h);
  const float side = config.cross_view_size * shorter;
  const float distance = config.cross_gap * shorter + 0.5f * side;
  // Face 0 below the centre, 1 right, 2 above, 3 left (screen seen from above, -Z at the top).
  static constexpr float kDirX[kFaceCount] = {0.0f, 1.0f, 0.0f, -1.0f};
  static constexpr float kDirY[kFaceCount] = {1.0f, 0.0f, -1.0f, 0.0f};
  const float cx = 0.5f * w + kDirX[face] * distance;
  const float cy = 0.5f * h + kDirY[face] * distance;
  return {cx - 0.5f * side, cy - 0.5f * side, side, side};
}

FacePlacement placeFace(const DisplayConfig& config, int face, cv::Size output, cv::Size2f crop) {
  checkFace(face);
  if (!(crop.width > 0.0f && crop.height > 0.0f))
    throw Error("display: face " + std::to_string(face) + " has an empty crop rectangle");
  const FaceSettings& settings = config.faces[static_cast<std::size_t>(face)];
  FacePlacement placement;
  placement.face = face;
  placement.output = config.layout == LayoutKind::Monitors ? face : 0;
  placement.view = viewRect(config, face, output);

  const vec2 cs = cosSinDeg(layoutRotationDeg(config.layout, face) + settings.rotation_deg);
  const float ac = std::abs(cs.x);
  const float as = std::abs(cs.y);
  // Fit the crop's rotated bounding box into the view.
  const float box_w = crop.width * ac + crop.height * as;
  const float box_h = crop.width * as + crop.height * ac;
  const float fit = std::min(placement.view.width / box_w, placement.view.height / box_h) * settings.scale;
  const vec2 quad_size(crop.width * fit, crop.height * fit);

  const float side = std::min(placement.view.width, placement.view.height);
  // Offset in the view's frame (+y up) turned into screen pixels (+y down), then rotated with it.
  const vec2 offset_view(settings.offset.x * side, -settings.offset.y * side);
  const mat3 rotate = rotation(cs);
  const vec2 offset_screen = vec2(rotate * vec3(offset_view, 0.0f));
  const vec2 centre(placement.view.x + 0.5f * placement.view.width,
                    placement.view.y + 0.5f * placement.view.height);

  const mat3 mirror = scaling({settings.mirror ? -1.0f : 1.0f, 1.0f});
  placement.unit_to_output = translation(centre + offset_screen) * rotate * scaling(quad_size) * mirror *
                             translation({-0.5f, -0.5f});
  return placement;
}

int faceViewPixels(const DisplayConfig& config, cv::Size output) {
  float side = 0.0f;
  for (int face = 0; face < kFaceCount; ++face) {
    const std::array<vec2, 4> corners = placeFace(config, face, output, {1.0f, 1.0f}).corners();
    side = std::max(side, glm::length(corners[1] - corners[0]));
  }
  return std::max(1, static_cast<int>(std::lround(side)));
}

cv::Size canvasSize(const DisplayConfig& config) {
  if (config.layout == LayoutKind::Monitors)
    return {2 * config.output_size.width, 2 * config.output_size.height};
  return config.output_size;
}

cv::Point outputOrigin(const DisplayConfig& config, int output) {
  if (output < 0 || output >= outputCount(config.layout))
    throw Error("display: output index " + std::to_string(output) + " outside the layout");
  return {(output % 2) * config.output_size.width, (output / 2) * config.output_size.height};
}

}  // namespace holo::display
