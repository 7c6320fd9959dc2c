#include "holo/reference/image_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::reference {

namespace {

vec3 displayed(const cv::Mat& m, int x, int y) {
  const vec3 c = rgbAt(m, x, y);
  if (!isFinite(c)) return vec3(0.0f);
  return glm::clamp(c, vec3(0.0f), vec3(1.0f));
}

void requireSameSize(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != CV_32FC3 || b.type() != CV_32FC3)
    throw InputError("", "image", "two CV_32FC3 images of the same size");
}

}  // namespace

cv::Mat foregroundRegion(const cv::Mat& with, const cv::Mat& without, float threshold) {
  requireSameSize(with, without);
  cv::Mat mask(with.rows, with.cols, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < with.rows; ++y)
    for (int x = 0; x < with.cols; ++x)
      if (glm::length(displayed(with, x, y) - displayed(without, x, y)) >= threshold)
        mask.at<uchar>(y, x) = 255;
  return mask;
}

double mse(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  requireSameSize(a, b);
  double sum = 0;
  long n = 0;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      if (!mask.empty() && mask.at<uchar>(y, x) == 0) continue;
      const vec3 d = displayed(a, x, y) - displayed(b, x, y);
      sum += double(glm::dot(d, d)) / 3.0;
      ++n;
    }
  return n > 0 ? sum / double(n) : 0.0;
}

cv::Mat errorMap(const cv::Mat& a, const cv::Mat& b, float max_error) {
  requireSameSize(a, b);
  cv::Mat gray(a.rows, a.cols, CV_8UC1);
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      const vec3 d = displayed(a, x, y) - displayed(b, x, y);
      const float e = glm::dot(d, d) / 3.0f / std::max(max_error, 1e-12f);
      gray.at<uchar>(y, x) = cv::saturate_cast<uchar>(std::clamp(e, 0.0f, 1.0f) * 255.0f);
    }
  cv::Mat colour;
  cv::applyColorMap(gray, colour, cv::COLORMAP_INFERNO);
  return colour;
}

}  // namespace holo::reference
