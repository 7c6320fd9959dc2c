#include "holo/display/test_pattern.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/display/layout.hpp"

namespace holo::display {

namespace {
cv::Rect toPixels(const PatternBox& box, cv::Size size) {
  const auto px = [](float f, int n) { return static_cast<int>(std::lround(f * static_cast<float>(n))); };
  const int x0 = px(box.x0, size.width), y0 = px(box.y0, size.height);
  return {x0, y0, px(box.x1, size.width) - x0, px(box.y1, size.height) - y0};
}
}  // namespace

cv::Vec3b patternColour(int face) {
  static const cv::Vec3b kColours[kFaceCount] = {{40, 40, 255}, {40, 255, 40}, {255, 60, 40}, {40, 255, 255}};
  if (face < 0 || face >= kFaceCount) throw Error("display: face index outside 0..3");
  return kColours[face];
}

const char* faceName(int face) {
  static const char* kNames[kFaceCount] = {"front +Z", "right +X", "back -Z", "left -X"};
  if (face < 0 || face >= kFaceCount) throw Error("display: face index outside 0..3");
  return kNames[face];
}

cv::Mat testPatternFace(int face, cv::Size size) {
  if (size.width < 16 || size.height < 16) throw Error("display: test pattern smaller than 16x16");
  const cv::Vec3b colour = patternColour(face);
  const cv::Scalar fill(colour[0], colour[1], colour[2]);
  cv::Mat image(size, CV_8UC3, cv::Scalar::all(0));
  const int frame =
      std::max(1, static_cast<int>(kPatternFrame * static_cast<float>(std::min(size.width, size.height))));
  cv::rectangle(image, cv::Rect(0, 0, size.width, size.height), fill * 0.5, frame);
  for (const PatternBox& box : {kPatternStem, kPatternTopBar, kPatternMiddleBar})
    cv::rectangle(image, toPixels(box, size), fill, cv::FILLED);
  // The label fits the lower-right quarter whatever the image size.
  const std::string label = std::to_string(face) + " " + faceName(face);
  const cv::Rect area = toPixels({0.45f, 0.65f, 0.95f, 0.95f}, size);
  int baseline = 0;
  const cv::Size unit = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, 1.0, 2, &baseline);
  const double scale = std::min(static_cast<double>(area.width) / unit.width,
                                static_cast<double>(area.height) / (unit.height + baseline));
  const int thickness = std::max(1, static_cast<int>(scale * 2.0));
  cv::putText(image, label, {area.x, area.y + static_cast<int>(unit.height * scale)},
              cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar::all(230), thickness, cv::LINE_AA);
  return image;
}

}  // namespace holo::display
