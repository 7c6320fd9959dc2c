#include "holo/display/cpu_compose.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "holo/core/error.hpp"

namespace holo::display {

namespace {

float srgbEncode(float c) {
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

// One channel of `image` at texel (x, y), clamped to the edge, on the [0, 1] scale (linear faces
// already exposed, clamped and NaN-free, as the shader does before encoding).
struct FaceSampler {
  const cv::Mat& image;
  float exposure;
  vec3 texel(int x, int y) const {
    x = std::clamp(x, 0, image.cols - 1);
    y = std::clamp(y, 0, image.rows - 1);
    if (image.type() == CV_8UC3) {
      const cv::Vec3b& p = image.at<cv::Vec3b>(y, x);
      return vec3(p[0], p[1], p[2]) / 255.0f;
    }
    const cv::Vec3f& p = image.at<cv::Vec3f>(y, x);
    vec3 c(p[0], p[1], p[2]);
    for (int k = 0; k < 3; ++k)  // the repair the GPU path makes before uploading
      c[k] = std::isnan(c[k]) ? 0.0f : std::clamp(c[k], 0.0f, std::numeric_limits<float>::max());
    return c;
  }
  // Bilinear at continuous texel coordinates (s, t), texel centres at k + 0.5.
  vec3 sample(float s, float t) const {
    const float fs = s - 0.5f, ft = t - 0.5f;
    const int x0 = static_cast<int>(std::floor(fs)), y0 = static_cast<int>(std::floor(ft));
    const float a = fs - static_cast<float>(x0), b = ft - static_cast<float>(y0);
    const vec3 top = glm::mix(texel(x0, y0), texel(x0 + 1, y0), a);
    const vec3 bottom = glm::mix(texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), a);
    return glm::mix(top, bottom, b);
  }
  vec3 encode(vec3 c) const {
    if (image.type() == CV_8UC3) return c;
    vec3 out;
    for (int k = 0; k < 3; ++k) {
      const float v = std::clamp(c[k] * exposure, 0.0f, 1.0f);
      out[k] = srgbEncode(v);
    }
    return out;
  }
};

template <class PerPixel>
void forEachCoveredPixel(const DisplayConfig& config, const std::array<cv::Mat, kFaceCount>& faces,
                         const std::array<cv::Rect2f, kFaceCount>& crops, PerPixel&& per_pixel) {
  for (int f = 0; f < kFaceCount; ++f) {
    const cv::Mat& face = faces[static_cast<std::size_t>(f)];
    const cv::Rect2f& crop = crops[static_cast<std::size_t>(f)];
    if (face.empty() || crop.width <= 0.0f || crop.height <= 0.0f) continue;
    if (face.type() != CV_8UC3 && face.type() != CV_32FC3)
      throw Error("display: face " + std::to_string(f) + " must be CV_8UC3 sRGB or CV_32FC3 linear");
    const FacePlacement placement = placeFace(config, f, config.output_size, crop.size());
    const mat3 output_to_unit = glm::inverse(placement.unit_to_output);
    // Only the pixels of the quad's bounding box can be covered.
    float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
    for (const vec2 c : placement.corners()) {
      x0 = std::min(x0, c.x), y0 = std::min(y0, c.y), x1 = std::max(x1, c.x), y1 = std::max(y1, c.y);
    }
    const cv::Point origin = outputOrigin(config, placement.output);
    const int ix0 = std::max(0, static_cast<int>(std::floor(x0)));
    const int iy0 = std::max(0, static_cast<int>(std::floor(y0)));
    const int ix1 = std::min(config.output_size.width, static_cast<int>(std::ceil(x1)));
    const int iy1 = std::min(config.output_size.height, static_cast<int>(std::ceil(y1)));
    const FaceSampler sampler{face, config.exposure};
    for (int y = iy0; y < iy1; ++y) {
      for (int x = ix0; x < ix1; ++x) {
        const vec2 unit =
            vec2(output_to_unit * vec3(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f, 1.0f));
        if (unit.x < 0.0f || unit.x >= 1.0f || unit.y < 0.0f || unit.y >= 1.0f) continue;
        per_pixel(origin.x + x, origin.y + y, sampler, crop, unit);
      }
    }
  }
}

}  // namespace

cv::Mat composeCanvasCpu(const DisplayConfig& config, const std::array<cv::Mat, kFaceCount>& faces,
                         const std::array<cv::Rect2f, kFaceCount>& crops) {
  cv::Mat canvas(canvasSize(config), CV_8UC3, cv::Scalar::all(0));
  forEachCoveredPixel(
      config, faces, crops, [&](int x, int y, const FaceSampler& sampler, const cv::Rect2f& crop, vec2 unit) {
        const vec3 c =
            sampler.encode(sampler.sample(crop.x + unit.x * crop.width, crop.y + unit.y * crop.height));
        cv::Vec3b& out = canvas.at<cv::Vec3b>(y, x);
        for (int k = 0; k < 3; ++k)
          out[k] = static_cast<uchar>(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
      });
  return canvas;
}

cv::Mat coverageCpu(const DisplayConfig& config, const std::array<cv::Mat, kFaceCount>& faces,
                    const std::array<cv::Rect2f, kFaceCount>& crops) {
  cv::Mat mask(canvasSize(config), CV_8UC1, cv::Scalar::all(0));
  forEachCoveredPixel(config, faces, crops, [&](int x, int y, const FaceSampler&, const cv::Rect2f&, vec2) {
    mask.at<uchar>(y, x) = 255;
  });
  return mask;
}

}  // namespace holo::display
