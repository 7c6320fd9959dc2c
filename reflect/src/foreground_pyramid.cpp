#include "holo/reflect/foreground_pyramid.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::reflect {
namespace {

// Bilinear read at a continuous position in pixel units (integer = pixel centre), clamped.
template <typename T>
T bilinear(const cv::Mat& m, float x, float y) {
  x = std::clamp(x, 0.0f, float(m.cols - 1));
  y = std::clamp(y, 0.0f, float(m.rows - 1));
  const int x0 = int(x), y0 = int(y);
  const int x1 = std::min(x0 + 1, m.cols - 1), y1 = std::min(y0 + 1, m.rows - 1);
  const float fx = x - float(x0), fy = y - float(y0);
  const T* r0 = m.ptr<T>(y0);
  const T* r1 = m.ptr<T>(y1);
  return (r0[x0] * (1.0f - fx) + r0[x1] * fx) * (1.0f - fy) + (r1[x0] * (1.0f - fx) + r1[x1] * fx) * fy;
}

// One dual-Kawase downsampling step: output pixel (x, y) covers input block [2x, 2x+1]^2 whose
// centre is read bilinearly with weight 4/8, plus four bilinear taps one pixel out diagonally,
// 1/8 each. Every tap is the mean of a 2x2 block, so the step is the 4x4 kernel below over input
// pixels 2x-1..2x+2 (OpenCV's SIMD filter2D, edges replicated), sampled at even pixels.
cv::Mat kawaseDown(const cv::Mat& in) {
  static const cv::Mat kernel = (cv::Mat_<float>(4, 4) << 1, 1, 1, 1,  //
                                 1, 5, 5, 1,                           //
                                 1, 5, 5, 1,                           //
                                 1, 1, 1, 1) /
                                32.0f;
  cv::Mat filtered;
  cv::filter2D(in, filtered, -1, kernel, cv::Point(1, 1), 0.0, cv::BORDER_REPLICATE);
  cv::Mat out(std::max(1, (in.rows + 1) / 2), std::max(1, (in.cols + 1) / 2), in.type());
  const std::size_t pixel_bytes = in.elemSize();
  for (int y = 0; y < out.rows; ++y) {
    const std::uint8_t* src = filtered.ptr<std::uint8_t>(2 * y);
    std::uint8_t* dst = out.ptr<std::uint8_t>(y);
    for (int x = 0; x < out.cols; ++x)
      std::memcpy(dst + std::size_t(x) * pixel_bytes, src + std::size_t(2 * x) * pixel_bytes, pixel_bytes);
  }
  return out;
}

}  // namespace

ForegroundPyramid::ForegroundPyramid(const cv::Mat& colour_bgr, const cv::Mat& mask, int levels) {
  if (colour_bgr.type() != CV_32FC3 || colour_bgr.empty())
    throw InputError("ForegroundPyramid", "colour", "a non-empty CV_32FC3 linear BGR image");
  if (mask.type() != CV_32FC1 && mask.type() != CV_8UC1)
    throw InputError("ForegroundPyramid", "mask", "CV_32FC1 in [0,1] or CV_8UC1");
  if (mask.size() != colour_bgr.size())
    throw InputError("ForegroundPyramid", "mask", "the colour image's size",
                     std::to_string(mask.cols) + "x" + std::to_string(mask.rows));
  if (levels < 1 || levels > kMaxPyramidLevels)
    throw InputError("ForegroundPyramid", "levels", "1.." + std::to_string(kMaxPyramidLevels),
                     std::to_string(levels));
  cv::Mat m;
  if (mask.type() == CV_8UC1)
    mask.convertTo(m, CV_32F, 1.0 / 255.0);
  else
    m = mask.clone();
  // Repairs: NaN/Inf mask -> 0, clamp to [0, 1]; non-finite colour -> 0.
  cv::patchNaNs(m, 0.0);
  cv::min(cv::max(m, 0.0), 1.0, m);
  cv::Mat c = colour_bgr.clone();
  c.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) {
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(p[k]) || p[k] < 0.0f) p[k] = 0.0f;
  });
  cv::Mat m3;
  cv::merge(std::vector<cv::Mat>{m, m, m}, m3);
  c = c.mul(m3);
  colour_.push_back(c);
  mask_.push_back(m);
  for (int l = 1; l < levels; ++l) {
    colour_.push_back(kawaseDown(colour_.back()));
    mask_.push_back(kawaseDown(mask_.back()));
  }
}

ForegroundSample ForegroundPyramid::sample(const vec2& pixel, float level) const {
  if (empty() || !std::isfinite(pixel.x) || !std::isfinite(pixel.y)) return {};
  level = std::isfinite(level) ? std::clamp(level, 0.0f, float(levels() - 1)) : 0.0f;
  const int l0 = int(level);
  const int l1 = std::min(l0 + 1, levels() - 1);
  const float f = level - float(l0);
  auto read = [&](int l, cv::Vec3f& c, float& w) {
    // Level-l pixel centre i covers level-0 pixels [i 2^l, (i+1) 2^l): centre (i + 0.5) 2^l - 0.5.
    const float s = std::ldexp(1.0f, -l);
    const float x = (pixel.x + 0.5f) * s - 0.5f, y = (pixel.y + 0.5f) * s - 0.5f;
    c = bilinear<cv::Vec3f>(colour_[std::size_t(l)], x, y);
    w = bilinear<float>(mask_[std::size_t(l)], x, y);
  };
  cv::Vec3f c0, c1;
  float w0 = 0.0f, w1 = 0.0f;
  read(l0, c0, w0);
  read(l1, c1, w1);
  const cv::Vec3f c = c0 * (1.0f - f) + c1 * f;
  const float w = std::clamp(w0 * (1.0f - f) + w1 * f, 0.0f, 1.0f);
  ForegroundSample out;
  out.weight = w;
  if (w > 1e-6f) out.radiance = vec3(c[2], c[1], c[0]) / w;  // un-premultiply, BGR -> RGB
  if (!isFinite(out.radiance)) out = {};
  return out;
}

// Filter variance (4^L - 1) / 4 plus the bilinear read's tent of width 2^L (variance 4^L / 6):
// sigma^2 = (5/12) 4^L - 1/4.
float pyramidSigmaPx(float level) {
  level = std::isfinite(level) ? std::max(level, 0.0f) : 0.0f;
  return std::sqrt(5.0f / 12.0f * std::exp2(2.0f * level) - 0.25f);
}

float pyramidLevelForSigma(float sigma_px) {
  if (!(sigma_px > 0.0f)) return 0.0f;
  const float s = std::min(sigma_px, 1e6f);
  return std::max(0.0f, 0.5f * std::log2((s * s + 0.25f) * 12.0f / 5.0f));
}

float reflectedLobeSigma(float roughness) {
  const float r = std::isfinite(roughness) ? std::clamp(roughness, 0.0f, 1.0f) : 1.0f;
  return std::min(std::sqrt(2.0f) * r * r, 1.0f);
}

float foregroundLevel(float roughness, float travel_m, float camera_distance_m, float focal_px, int levels) {
  if (levels <= 1) return 0.0f;
  if (!(travel_m > 0.0f) || !(camera_distance_m > 0.0f) || !(focal_px > 0.0f) || !std::isfinite(travel_m) ||
      !std::isfinite(camera_distance_m) || !std::isfinite(focal_px))
    return 0.0f;
  const float sigma_px = travel_m * std::tan(reflectedLobeSigma(roughness)) * focal_px / camera_distance_m;
  return std::clamp(pyramidLevelForSigma(sigma_px), 0.0f, float(levels - 1));
}

}  // namespace holo::reflect
