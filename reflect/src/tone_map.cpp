#include "holo/reflect/tone_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "holo/core/image.hpp"

namespace holo::reflect {
namespace {

constexpr int kSrgbSteps = 1 << 14;

// sRGB code values of linear [0, 1] in kSrgbSteps steps, rounded: the exact curve costs a pow
// per channel, the table a load; the steepest part (slope 12.92 near black) moves less than 0.2
// of a code value per step.
const std::array<std::uint8_t, kSrgbSteps + 1>& srgbTable() {
  static const std::array<std::uint8_t, kSrgbSteps + 1> table = [] {
    std::array<std::uint8_t, kSrgbSteps + 1> t{};
    for (int i = 0; i <= kSrgbSteps; ++i)
      t[std::size_t(i)] =
          cv::saturate_cast<uchar>(linearToSrgb(float(i) / float(kSrgbSteps)) * 255.0f + 0.5f);
    return t;
  }();
  return table;
}

std::uint8_t encode(const std::array<std::uint8_t, kSrgbSteps + 1>& table, float linear) {
  const float clamped = std::min(std::max(linear, 0.0f), 1.0f);
  return table[std::size_t(clamped * float(kSrgbSteps) + 0.5f)];
}

}  // namespace

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

cv::Vec3b toneMapPixel(const vec3& rgb, float exposure) {
  vec3 c = rgb * exposure;
  if (!isFinite(c)) c = vec3(0.0f);
  c = glm::max(c, vec3(0.0f));
  const float l = luminance(c);
  if (l > 0.0f) c *= (1.0f / (1.0f + l));
  const auto& table = srgbTable();
  return {encode(table, c.b), encode(table, c.g), encode(table, c.r)};
}

vec3 toneMapCodes(const vec3& rgb, float exposure) {
  vec3 c = rgb * exposure;
  if (!isFinite(c)) c = vec3(0.0f);
  c = glm::max(c, vec3(0.0f));
  const float l = luminance(c);
  if (l > 0.0f) c *= (1.0f / (1.0f + l));
  vec3 codes;
  for (int i = 0; i < 3; ++i) {
    const float v = std::min(c[i], 1.0f);
    codes[i] = 255.0f * (v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f);
  }
  return codes;
}

float largestCodeChange(float radiance, float exposure) {
  const float exposed = 2.0f * std::abs(radiance) * exposure;
  if (!std::isfinite(exposed)) return std::numeric_limits<float>::infinity();
  return 255.0f * linearToSrgb(std::min(exposed, 1.0f));
}

cv::Mat toneMap(const cv::Mat& hdr, float exposure) {
  cv::Mat out(hdr.rows, hdr.cols, CV_8UC3);
  for (int y = 0; y < hdr.rows; ++y)
    for (int x = 0; x < hdr.cols; ++x) out.at<cv::Vec3b>(y, x) = toneMapPixel(rgbAt(hdr, x, y), exposure);
  return out;
}

cv::Mat toneMapCovered(const cv::Mat& hdr, const std::vector<std::uint32_t>& pixels, float exposure) {
  cv::Mat out(hdr.rows, hdr.cols, CV_8UC3, cv::Scalar::all(0));
  const std::size_t w = std::size_t(hdr.cols);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const int x = int(pixels[k] % w), y = int(pixels[k] / w);
                        out.at<cv::Vec3b>(y, x) = toneMapPixel(rgbAt(hdr, x, y), exposure);
                      }
                    });
  return out;
}

}  // namespace holo::reflect
