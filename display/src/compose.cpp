#include "compose.hpp"

#include "holo/core/error.hpp"
#include "holo/display/auto_fit.hpp"

namespace holo::display {

std::array<cv::Rect2f, kFaceCount> chooseCrops(const DisplayConfig& config, const FaceImages& faces,
                                               const FaceImages* coverage,
                                               const std::array<cv::Rect2f, kFaceCount>& previous) {
  std::array<cv::Rect2f, kFaceCount> crops = previous;
  for (int f = 0; f < kFaceCount; ++f) {
    const cv::Mat& face = faces[static_cast<std::size_t>(f)];
    if (face.empty()) continue;
    if (face.type() != CV_8UC3 && face.type() != CV_32FC3)
      throw Error("display: face " + std::to_string(f) + " must be CV_8UC3 sRGB or CV_32FC3 linear");
    crops[static_cast<std::size_t>(f)] =
        config.auto_fit.enabled
            ? objectCrop(face, coverage ? (*coverage)[static_cast<std::size_t>(f)] : cv::Mat(),
                         config.auto_fit)
            : cv::Rect2f(0.0f, 0.0f, static_cast<float>(face.cols), static_cast<float>(face.rows));
  }
  return crops;
}

void drawOutput(QuadRenderer& renderer, const DisplayConfig& config, int output, cv::Point origin,
                cv::Size size, int framebuffer_height, const std::array<cv::Rect2f, kFaceCount>& crops) {
  renderer.beginOutput(origin, size, framebuffer_height);
  for (int f = 0; f < kFaceCount; ++f) {
    const cv::Rect2f& crop = crops[static_cast<std::size_t>(f)];
    if (crop.width <= 0.0f || crop.height <= 0.0f) continue;
    const FacePlacement placement = placeFace(config, f, size, crop.size());
    if (placement.output != output) continue;
    renderer.drawFace(placement, crop, config.exposure);
  }
}

}  // namespace holo::display
