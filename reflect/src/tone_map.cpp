#include "holo/reflect/tone_map.hpp"

#include <cmath>

#include "holo/core/image.hpp"

namespace holo::reflect {

float autoExposure(const cv::Mat& hdr) {
  double log_sum = 0;
  long count = 0;
  for (int y = 0; y < hdr.rows; ++y)
    for (int x = 0; x < hdr.cols; ++x) {
      const float l = luminance(rgbAt(hdr, x, y));
      if (std::isfinite(l) && l > 1e-6f) {
        log_sum += std::log(double(l));
        ++count;
      }
    }
  if (count == 0) return 1.0f;
  return float(0.18 / std::exp(log_sum / double(count)));
}

cv::Mat toneMap(const cv::Mat& hdr, float exposure) {
  cv::Mat out(hdr.rows, hdr.cols, CV_8UC3);
  for (int y = 0; y < hdr.rows; ++y)
    for (int x = 0; x < hdr.cols; ++x) {
      vec3 c = rgbAt(hdr, x, y) * exposure;
      if (!isFinite(c)) c = vec3(0.0f);
      c = glm::max(c, vec3(0.0f));
      const float l = luminance(c);
      if (l > 0.0f) c *= (1.0f / (1.0f + l));
      out.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(linearToSrgb(c.b) * 255.0f + 0.5f),
                                          cv::saturate_cast<uchar>(linearToSrgb(c.g) * 255.0f + 0.5f),
                                          cv::saturate_cast<uchar>(linearToSrgb(c.r) * 255.0f + 0.5f));
    }
  return out;
}

}  // namespace holo::reflect
