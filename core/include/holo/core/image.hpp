// Linear HDR images and conversions. Convention: every cv::Mat image in the project keeps
// OpenCV's BGR channel order (CV_8UC3 sRGB for display/camera colour, CV_32FC3 linear radiance
// in W/(sr m^2) up to an arbitrary global scale for HDR); glm::vec3 colours are RGB. Use the
// helpers below to cross between the two so the order is converted in one place.
#pragma once

#include <opencv2/core.hpp>

#include "holo/core/math.hpp"

namespace holo {

inline vec3 rgbAt(const cv::Mat& bgr32f, int x, int y) {
  const auto& p = bgr32f.at<cv::Vec3f>(y, x);
  return {p[2], p[1], p[0]};
}
inline void setRgb(cv::Mat& bgr32f, int x, int y, const vec3& rgb) {
  bgr32f.at<cv::Vec3f>(y, x) = cv::Vec3f(rgb.b, rgb.g, rgb.r);
}

float srgbToLinear(float encoded);  // [0,1] -> [0,1]
float linearToSrgb(float linear);   // [0,1] -> [0,1], input clamped

// CV_8UC3 sRGB -> CV_32FC3 linear in [0,1].
cv::Mat srgb8ToLinear(const cv::Mat& bgr8);
// CV_32FC3 linear -> CV_8UC3 sRGB, after multiplying by `exposure` and clamping to [0,1].
cv::Mat linearToSrgb8(const cv::Mat& bgr32f, float exposure = 1.0f);

struct RepairCounts {
  long nan = 0;
  long inf = 0;
  long negative = 0;
  long total() const { return nan + inf + negative; }
};
// Replaces NaN by 0, +Inf by the largest finite value in the image (a sum over pixels must stay
// finite), and negatives (and -Inf) by 0 in a
// CV_32F image of any channel count; returns how many values of each kind were repaired.
RepairCounts sanitizeRadiance(cv::Mat& image32f);

}  // namespace holo
