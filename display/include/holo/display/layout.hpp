// Quad-view layout: where each of the four face images lands on the display outputs. Pure math,
// no OpenGL; the GPU path (QuadRenderer) applies exactly the matrices computed here.
//
// Faces. Face f = 0..3 is the pyramid face whose outward horizontal normal is +Z rotated by
// f * 90 degrees about +Y: 0 = +Z (front), 1 = +X (right), 2 = -Z (back), 3 = -X (left).
//
// Pixel coordinates. Output pixels are continuous coordinates with +x right, +y down and the
// origin at the top-left corner of the output (pixel (i, j) covers [i, i+1] x [j, j+1]). A face
// image is addressed by "unit" coordinates (u, v) in [0, 1]^2 of its crop rectangle, u right and
// v down in the image as stored (row 0 at the top).
//
// Layouts.
//  * monitors: four outputs, output k shows face k, fitted (aspect kept) into the whole output.
//  * cross: one output (the screen under the pyramid, seen from above with -Z at the top and +X
//    at the right). The four views are squares around the centre; face 0 sits below the centre,
//    1 right, 2 above, 3 left, each rotated clockwise on screen by 180, 90, 0, 270 degrees so that
//    the view's "up" points away from the centre: a screen point farther from the centre is
//    reflected higher in the 45-degree glass, so "away from the centre" is "up" for the viewer.
//
// Transform of one face, applied to the unit quad in this order: centre the crop, mirror
// left-right (Pepper's ghost reverses the image, so mirror = true shows it the right way round),
// scale to fit the view (times the face's scale), rotate clockwise by the layout's angle plus the
// face's extra rotation, offset (in the view's own frame: +x right, +y up, in units of the view's
// side) and translate to the view's centre.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <string>

#include "holo/core/math.hpp"

namespace holo::display {

inline constexpr int kFaceCount = 4;

enum class LayoutKind { Monitors, Cross };
const char* layoutName(LayoutKind kind);  // "monitors" or "cross"

struct FaceSettings {
  bool mirror = true;         // reverse left-right (undoes the glass's reflection)
  vec2 offset{0.0f};          // view frame (+x right, +y up), units of the view's side
  float scale = 1.0f;         // > 0, multiplies the fitted size
  float rotation_deg = 0.0f;  // extra clockwise rotation on screen, degrees
  int monitor = -1;           // monitors layout: GLFW monitor index; -1 = the face index
};

struct AutoFitSettings {
  bool enabled = false;
  float margin = 0.05f;     // added on each side, as a fraction of the object's larger side
  float threshold = 0.02f;  // a pixel is "object" when a channel exceeds this ([0,1] scale)
};

struct DisplayConfig {
  LayoutKind layout = LayoutKind::Cross;
  // Size of each output when it is not a real monitor (headless, or a window in windowed mode):
  // a Full HD screen unless configured.
  cv::Size output_size{1920, 1080};
  // cross layout, fractions of the output's shorter side: side of each view square and the
  // distance from the centre to the inner edge of each view. The views stay on the output when
  // gap + view_size <= 1/2; the defaults (1/3, 1/6) tile the shorter side exactly.
  float cross_view_size = 1.0f / 3.0f;
  float cross_gap = 1.0f / 6.0f;
  std::array<FaceSettings, kFaceCount> faces{};
  AutoFitSettings auto_fit{};
  float exposure = 1.0f;                     // multiplies linear HDR faces before sRGB encoding
  bool fullscreen = true;                    // windows: fullscreen on the chosen monitors, else plain windows
  std::string source = "built-in defaults";  // the file the settings came from, for errors
};

int outputCount(LayoutKind kind);  // 4 for monitors, 1 for cross

// Where face `face` goes: on output `output`, inside the view rectangle `view` (output pixels),
// with `unit_to_output` mapping unit crop coordinates (u, v, 1) to output pixels (x, y, 1).
struct FacePlacement {
  int face = 0;
  int output = 0;
  cv::Rect2f view;
  mat3 unit_to_output{1.0f};
  vec2 apply(vec2 unit) const;
  // Output positions of the crop's corners: top-left, top-right, bottom-right, bottom-left
  // (as stored in the face image).
  std::array<vec2, 4> corners() const;
};

// The layout's own clockwise rotation of face `face` in degrees (cross: 180, 90, 0, 270;
// monitors: 0), before the face's extra rotation.
float layoutRotationDeg(LayoutKind kind, int face);

// The view rectangle of `face` on an output of size `output`.
cv::Rect2f viewRect(const DisplayConfig& config, int face, cv::Size output);

// Places face `face` whose crop rectangle has size `crop` (pixels, > 0) on an output of size
// `output`. The crop is fitted with its aspect kept so that its rotated bounding box fills the
// view, then scaled by the face's scale.
FacePlacement placeFace(const DisplayConfig& config, int face, cv::Size output, cv::Size2f crop);

// The side in output pixels of a square face image as placed on an output of size `output`: the
// largest over the four faces (their scale and rotation included), rounded, at least 1. Rendering
// each face at this many pixels shows it without upscaling and without pixels the screen cannot
// show (cross 1920x1080 with the default view 1/3 of the shorter side: 360; monitors of
// 1920x1080: 1080).
int faceViewPixels(const DisplayConfig& config, cv::Size output);

// Headless canvas: the outputs side by side in one image (monitors: a 2x2 sheet, output k at
// column k % 2, row k / 2; cross: the one output).
cv::Size canvasSize(const DisplayConfig& config);
cv::Point outputOrigin(const DisplayConfig& config, int output);

}  // namespace holo::display
