#include "holo/core/image.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace holo {

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float l) {
  l = std::clamp(l, 0.0f, 1.0f);
  return l <= 0.0031308f ? 12.92f * l : 1.055f * std::pow(l, 1.0f / 2.4f) - 0.055f;
}

cv::Mat srgb8ToLinear(const cv::Mat& bgr8) {
  CV_Assert(bgr8.type() == CV_8UC3);
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[static_cast<std::size_t>(i)] = srgbToLinear(float(i) / 255.0f);
    return t;
  }();
  cv::Mat out(bgr8.size(), CV_32FC3);
  bgr8.forEach<cv::Vec3b>([&](const cv::Vec3b& p, const int* pos) {
    out.at<cv::Vec3f>(pos[0], pos[1]) = cv::Vec3f(table[p[0]], table[p[1]], table[p[2]]);
  });
  return out;
}

cv::Mat linearToSrgb8(const cv::Mat& bgr32f, float exposure) {
  CV_Assert(bgr32f.type() == CV_32FC3);
  // A 4096-entry table over [0,1] keeps the round trip within one 8-bit step.
  static const std::array<std::uint8_t, 4097> table = [] {
    std::array<std::uint8_t, 4097> t{};
    for (int i = 0; i <= 4096; ++i)
      t[static_cast<std::size_t>(i)] =
          static_cast<std::uint8_t>(std::lround(255.0f * linearToSrgb(float(i) / 4096.0f)));
    return t;
  }();
  auto encode = [&](float v) {
    v *= exposure;
    if (!(v > 0.0f)) return std::uint8_t{0};
    if (v >= 1.0f) return std::uint8_t{255};
    return table[static_cast<std::size_t>(v * 4096.0f + 0.5f)];
  };
  cv::Mat out(bgr32f.size(), CV_8UC3);
  bgr32f.forEach<cv::Vec3f>([&](const cv::Vec3f& p, const int* pos) {
    out.at<cv::Vec3b>(pos[0], pos[1]) = cv::Vec3b(encode(p[0]), encode(p[1]), encode(p[2]));
  });
  return out;
}

RepairCounts sanitizeRadiance(cv::Mat& image) {
  CV_Assert(image.depth() == CV_32F);
  RepairCounts counts;
  float max_finite = 0.0f;
  const auto total = image.total() * static_cast<std::size_t>(image.channels());
  auto* begin = image.isContinuous() ? image.ptr<float>() : nullptr;
  cv::Mat tmp;
  if (!begin) {
    tmp = image.clone();
    begin = tmp.ptr<float>();
  }
  for (std::size_t i = 0; i < total; ++i)
    if (std::isfinite(begin[i])) max_finite = std::max(max_finite, begin[i]);
  for (std::size_t i = 0; i < total; ++i) {
    float& v = begin[i];
    if (std::isnan(v)) {
      ++counts.nan;
      v = 0.0f;
    } else if (std::isinf(v)) {
      ++counts.inf;
      v = v > 0 ? max_finite : 0.0f;
    } else if (v < 0.0f) {
      ++counts.negative;
      v = 0.0f;
    }
  }
  if (!tmp.empty()) tmp.copyTo(image);
  return counts;
}

}  // namespace holo
