// An asymmetric alignment pattern per face: a letter F in the face's colour on black, with a thin
// frame and the face's name. The F shows every rotation and mirroring at a glance (a technician
// aligning the pyramid reads an F the right way round on every face), and the tests read its
// pixels back to check the layouts.
#pragma once

#include <opencv2/core.hpp>

namespace holo::display {

// Geometry of the F, in fractions of the image's width (x) and height (y), [lo, hi).
struct PatternBox {
  float x0, y0, x1, y1;
};
inline constexpr PatternBox kPatternStem{0.20f, 0.15f, 0.35f, 0.85f};
inline constexpr PatternBox kPatternTopBar{0.20f, 0.15f, 0.80f, 0.30f};
inline constexpr PatternBox kPatternMiddleBar{0.20f, 0.45f, 0.60f, 0.58f};
// Frame width in fractions of the shorter side; drawn in half the face colour.
inline constexpr float kPatternFrame = 0.02f;

// Face colours (BGR): 0 red, 1 green, 2 blue, 3 yellow.
cv::Vec3b patternColour(int face);
const char* faceName(int face);  // "front +Z", "right +X", "back -Z", "left -X"

// CV_8UC3 sRGB pattern of face `face` (0..3). The name is written in the lower-right quarter,
// below the middle bar and right of the stem (x in [0.45, 0.95], y in [0.65, 0.95]).
cv::Mat testPatternFace(int face, cv::Size size);

}  // namespace holo::display
