#include "holo/display/auto_fit.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::display {

namespace {
cv::Mat objectMask(const cv::Mat& image, float threshold) {
  if (image.type() != CV_8UC3 && image.type() != CV_32FC3)
    throw Error("display: auto-fit expects a CV_8UC3 or CV_32FC3 face image");
  const double level = image.depth() == CV_8U ? threshold * 255.0 : threshold;
  cv::Mat channels[3];
  cv::split(image, channels);
  cv::Mat mask = cv::Mat::zeros(image.size(), CV_8UC1);
  for (const cv::Mat& channel : channels) {
    cv::Mat above;
    cv::compare(channel, level, above, cv::CMP_GT);  // NaN compares false: black
    mask |= above;
  }
  return mask;
}
}  // namespace

cv::Rect2f objectCrop(const cv::Mat& image, const cv::Mat& mask, const AutoFitSettings& settings) {
  if (image.empty()) throw Error("display: auto-fit of an empty face image");
  const cv::Rect2f whole(0.0f, 0.0f, static_cast<float>(image.cols), static_cast<float>(image.rows));
  cv::Mat object;
  if (!mask.empty()) {
    if (mask.type() != CV_8UC1 || mask.size() != image.size())
      throw Error("display: auto-fit mask must be CV_8UC1 of the face image's size");
    object = mask;
  } else {
    object = objectMask(image, settings.threshold);
  }
  const cv::Rect box = cv::boundingRect(object);
  if (box.area() <= 0) return whole;
  const float grow = settings.margin * static_cast<float>(std::max(box.width, box.height));
  const float x0 = std::max(0.0f, static_cast<float>(box.x) - grow);
  const float y0 = std::max(0.0f, static_cast<float>(box.y) - grow);
  const float x1 = std::min(whole.width, static_cast<float>(box.x + box.width) + grow);
  const float y1 = std::min(whole.height, static_cast<float>(box.y + box.height) + grow);
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace holo::display
