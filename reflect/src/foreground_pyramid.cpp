#include "holo/reflect/foreground_pyramid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

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
// Only the output pixels in out_box are computed: filter2D on a sub-matrix reads the parent's
// pixels around it and replicates only at the true image border, so they equal the full build.
void kawaseDown(const cv::Mat& in, cv::Mat& out, const cv::Rect& out_box, cv::Mat& scratch) {
  static const cv::Mat kernel = (cv::Mat_<float>(4, 4) << 1, 1, 1, 1,  //
                                 1, 5, 5, 1,                           //
                                 1, 5, 5, 1,                           //
                                 1, 1, 1, 1) /
                                32.0f;
  if (out_box.empty()) return;
  const cv::Rect in_box(2 * out_box.x, 2 * out_box.y, 2 * out_box.width - 1, 2 * out_box.height - 1);
  // A view of the full-size scratch: filter2D's create() keeps it, so no allocation per build.
  cv::Mat filtered = scratch(cv::Rect(0, 0, in_box.width, in_box.height));
  cv::filter2D(in(in_box), filtered, -1, kernel, cv::Point(1, 1), 0.0, cv::BORDER_REPLICATE);
  const std::size_t pixel_bytes = in.elemSize();
  for (int y = 0; y < out_box.height; ++y) {
    const std::uint8_t* src = filtered.ptr<std::uint8_t>(2 * y);
    std::uint8_t* dst = out.ptr<std::uint8_t>(out_box.y + y) + std::size_t(out_box.x) * pixel_bytes;
    for (int x = 0; x < out_box.width; ++x)
      std::memcpy(dst + std::size_t(x) * pixel_bytes, src + std::size_t(2 * x) * pixel_bytes, pixel_bytes);
  }
}

// The output pixels of one Kawase step that can be non-zero when the input is non-zero only in
// `in_box`: output x reads input 2x-1..2x+2, so x in [ceil((x0-2)/2), floor((x1+1)/2)], clipped.
cv::Rect kawaseSupport(const cv::Rect& in_box, cv::Size out_size) {
  if (in_box.empty()) return {};
  const int x0 = std::max(0, (in_box.x - 1) / 2), y0 = std::max(0, (in_box.y - 1) / 2);
  const int last_x = std::min(out_size.width - 1, (in_box.x + in_box.width) / 2);
  const int last_y = std::min(out_size.height - 1, (in_box.y + in_box.height) / 2);
  return {x0, y0, last_x - x0 + 1, last_y - y0 + 1};
}

float repairedMask(float v) {
  return v > 0.0f ? std::min(v, 1.0f) : 0.0f;
}  // NaN, <0 -> 0; Inf -> 1
float repairedMask(std::uint8_t v) {
  return float(v) * (1.0f / 255.0f);
}
float repairedColour(float v) {
  return std::isfinite(v) && v > 0.0f ? v : 0.0f;
}

// The bounding box of the repaired mask's non-zero pixels (empty when there are none).
template <typename M>
cv::Rect maskBox(const cv::Mat& mask) {
  int x0 = mask.cols, y0 = mask.rows, x1 = -1, y1 = -1;
  for (int y = 0; y < mask.rows; ++y) {
    const M* row = mask.ptr<M>(y);
    int first = -1, last = -1;
    for (int x = 0; x < mask.cols; ++x)
      if (repairedMask(row[x]) > 0.0f) {
        if (first < 0) first = x;
        last = x;
      }
    if (first < 0) continue;
    x0 = std::min(x0, first);
    x1 = std::max(x1, last);
    y0 = std::min(y0, y);
    y1 = y;
  }
  return x1 < 0 ? cv::Rect() : cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
}

// Level 0 inside box: the repaired mask and the repaired colour premultiplied by it.
template <typename M>
void writeLevel0(const cv::Mat& colour_bgr, const cv::Mat& mask, const cv::Rect& box, cv::Mat& colour_out,
                 cv::Mat& mask_out) {
  for (int y = box.y; y < box.y + box.height; ++y) {
    const M* m = mask.ptr<M>(y);
    const cv::Vec3f* c = colour_bgr.ptr<cv::Vec3f>(y);
    float* mo = mask_out.ptr<float>(y);
    cv::Vec3f* co = colour_out.ptr<cv::Vec3f>(y);
    for (int x = box.x; x < box.x + box.width; ++x) {
      const float w = repairedMask(m[x]);
      mo[x] = w;
      for (int k = 0; k < 3; ++k) co[x][k] = repairedColour(c[x][k]) * w;
    }
  }
}

}  // namespace

ForegroundPyramid::ForegroundPyramid(const cv::Mat& colour_bgr, const cv::Mat& mask, int levels) {
  build(colour_bgr, mask, levels);
}

void ForegroundPyramid::build(const cv::Mat& colour_bgr, const cv::Mat& mask, int levels) {
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
  levels_ = 0;  // empty until built (an exception below leaves it empty)
  if (colour_.size() < std::size_t(levels)) {
    colour_.resize(std::size_t(levels));
    mask_.resize(std::size_t(levels));
    support_.resize(std::size_t(levels));
  }
  // Level sizes; a buffer of the right size keeps its storage and only its last support is
  // cleared, any other is (re)allocated as zeros.
  cv::Size size = colour_bgr.size();
  for (int l = 0; l < levels; ++l) {
    const std::size_t i = std::size_t(l);
    if (colour_[i].size() != size || mask_[i].size() != size) {
      colour_[i] = cv::Mat(size, CV_32FC3, cv::Scalar::all(0));
      mask_[i] = cv::Mat(size, CV_32FC1, cv::Scalar(0));
    } else if (!support_[i].empty()) {
      colour_[i](support_[i]).setTo(cv::Scalar::all(0));
      mask_[i](support_[i]).setTo(cv::Scalar(0));
    }
    support_[i] = {};
    size = cv::Size(std::max(1, (size.width + 1) / 2), std::max(1, (size.height + 1) / 2));
  }
  if (filtered_colour_.size() != colour_bgr.size()) {
    filtered_colour_.create(colour_bgr.size(), CV_32FC3);
    filtered_mask_.create(colour_bgr.size(), CV_32FC1);
  }

  // Repairs (not errors): NaN/Inf mask -> 0 (+Inf -> 1), clamped to [0, 1]; non-finite or
  // negative colour -> 0.
  if (mask.type() == CV_8UC1) {
    support_[0] = maskBox<std::uint8_t>(mask);
    writeLevel0<std::uint8_t>(colour_bgr, mask, support_[0], colour_[0], mask_[0]);
  } else {
    support_[0] = maskBox<float>(mask);
    writeLevel0<float>(colour_bgr, mask, support_[0], colour_[0], mask_[0]);
  }
  for (int l = 1; l < levels; ++l) {
    const std::size_t i = std::size_t(l);
    support_[i] = kawaseSupport(support_[i - 1], colour_[i].size());
    kawaseDown(colour_[i - 1], colour_[i], support_[i], filtered_colour_);
    kawaseDown(mask_[i - 1], mask_[i], support_[i], filtered_mask_);
  }
  levels_ = levels;
}

std::size_t ForegroundPyramid::checkedLevel(int level) const {
  if (level < 0 || level >= levels_)
    throw std::out_of_range("ForegroundPyramid: level " + std::to_string(level));
  return std::size_t(level);
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
  // At a whole level the next one's share is 0: a finite read times 0 adds nothing, so it is not
  // read (every level is made of finite values).
  if (f > 0.0f) read(l1, c1, w1);
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
  return foregroundLevelForLobe(reflectedLobeSigma(roughness), travel_m, camera_distance_m, focal_px, levels);
}

float foregroundLevelForLobe(float lobe_sigma_rad, float travel_m, float camera_distance_m, float focal_px,
                             int levels) {
  if (levels <= 1) return 0.0f;
  if (!(travel_m > 0.0f) || !(camera_distance_m > 0.0f) || !(focal_px > 0.0f) || !std::isfinite(travel_m) ||
      !std::isfinite(camera_distance_m) || !std::isfinite(focal_px) || !(lobe_sigma_rad >= 0.0f))
    return 0.0f;
  const float sigma_px = travel_m * std::tan(std::min(lobe_sigma_rad, 1.0f)) * focal_px / camera_distance_m;
  return std::clamp(pyramidLevelForSigma(sigma_px), 0.0f, float(levels - 1));
}

std::vector<LobeComponent> ggxLobeMixture(int components) {
  if (components < 1 || components > kMaxLobeComponents)
    throw InputError("ggxLobeMixture", "components", "1.." + std::to_string(kMaxLobeComponents),
                     std::to_string(components));
  if (components == 1) return {LobeComponent{}};
  std::vector<LobeComponent> mixture;
  for (int k = 0; k < components; ++k) {
    // chi^2(2) is exponential with mean 2: the p-quantile is -2 ln(1 - p).
    const double p = (double(k) + 0.5) / double(components);
    const double g = -2.0 * std::log(1.0 - p);
    mixture.push_back({float(std::sqrt(2.0 / g)), 1.0f / float(components)});
  }
  return mixture;
}

}  // namespace holo::reflect
