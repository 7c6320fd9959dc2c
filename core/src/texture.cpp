#include "holo/core/texture.hpp"

#include "holo/core/image.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace holo {

namespace {

// Texel index for integer coordinate i on an axis of n texels under the wrap mode.
int wrapIndex(int i, int n, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge:
      return std::clamp(i, 0, n - 1);
    case TextureWrap::MirroredRepeat: {
      const int period = 2 * n;
      int m = i % period;
      if (m < 0) m += period;
      return m < n ? m : period - 1 - m;
    }
    case TextureWrap::Repeat:
      break;
  }
  const int m = i % n;
  return m < 0 ? m + n : m;
}

// The same coordinate within one period of the wrap (two for mirroring), so scaling it to texels
// cannot overflow an int however far outside [0,1] a uv lies.
float reduce(float u, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge:
      return std::clamp(u, -1.0f, 2.0f);
    case TextureWrap::MirroredRepeat:
      return u - 2.0f * std::floor(0.5f * u);
    case TextureWrap::Repeat:
      break;
  }
  return u - std::floor(u);
}

// A stored 8-bit value as linear light, per encoding: every texel is decoded before it is
// filtered, as GPUs do for sRGB formats (filtering encoded values darkens every edge).
using DecodeTable = std::array<float, 256>;

const DecodeTable& decodeTable(TextureEncoding encoding) {
  static const DecodeTable linear = [] {
    DecodeTable t{};
    for (int i = 0; i < 256; ++i) t[std::size_t(i)] = static_cast<float>(i) / 255.0f;
    return t;
  }();
  static const DecodeTable srgb = [] {
    DecodeTable t{};
    for (int i = 0; i < 256; ++i) t[std::size_t(i)] = srgbToLinear(static_cast<float>(i) / 255.0f);
    return t;
  }();
  return encoding == TextureEncoding::Srgb ? srgb : linear;
}

// Alpha is linear in every encoding.
vec4 texelAt(const cv::Mat& level, int x, int y, const DecodeTable& decode) {
  const uchar* p = level.ptr<uchar>(y) + x * level.channels();
  const float a = level.channels() == 4 ? p[3] / 255.0f : 1.0f;
  return {decode[p[2]], decode[p[1]], decode[p[0]], a};
}

// One level, texel centres at half-integers (glTF and OpenGL convention).
vec4 sampleLevel(const cv::Mat& level, const TextureSampler& s, vec2 uv, bool linear,
                 const DecodeTable& decode) {
  const float x = reduce(uv.x, s.wrap_u) * static_cast<float>(level.cols);
  const float y = reduce(uv.y, s.wrap_v) * static_cast<float>(level.rows);
  if (!linear) {
    return texelAt(level, wrapIndex(static_cast<int>(std::floor(x)), level.cols, s.wrap_u),
                   wrapIndex(static_cast<int>(std::floor(y)), level.rows, s.wrap_v), decode);
  }
  const float fx = x - 0.5f, fy = y - 0.5f;
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float tx = fx - x0f, ty = fy - y0f;
  const int x0 = static_cast<int>(x0f), y0 = static_cast<int>(y0f);
  const int xa = wrapIndex(x0, level.cols, s.wrap_u), xb = wrapIndex(x0 + 1, level.cols, s.wrap_u);
  const int ya = wrapIndex(y0, level.rows, s.wrap_v), yb = wrapIndex(y0 + 1, level.rows, s.wrap_v);
  const vec4 top = glm::mix(texelAt(level, xa, ya, decode), texelAt(level, xb, ya, decode), tx);
  const vec4 bottom = glm::mix(texelAt(level, xa, yb, decode), texelAt(level, xb, yb, decode), tx);
  return glm::mix(top, bottom, ty);
}

// The next mip level: each texel the mean light of the (up to) 2x2 texels of `level` it covers
// (an odd last row or column is averaged alone), in `level`'s encoding. Works on bytes, so a
// large texture needs no float copy.
cv::Mat halveLevel(const cv::Mat& level, TextureEncoding encoding) {
  const DecodeTable& decode = decodeTable(encoding);
  const int channels = level.channels();
  cv::Mat out((level.rows + 1) / 2, (level.cols + 1) / 2, level.type());
  for (int y = 0; y < out.rows; ++y) {
    const int y0 = 2 * y, y1 = std::min(2 * y + 1, level.rows - 1);
    uchar* o = out.ptr<uchar>(y);
    for (int x = 0; x < out.cols; ++x) {
      const int x0 = 2 * x, x1 = std::min(2 * x + 1, level.cols - 1);
      for (int c = 0; c < channels; ++c) {
        const bool is_alpha = c == 3;
        float sum = 0.0f;
        for (const int yy : {y0, y1})
          for (const int xx : {x0, x1}) {
            const uchar v = level.ptr<uchar>(yy)[xx * channels + c];
            sum += is_alpha ? v / 255.0f : decode[v];
          }
        const float mean = 0.25f * sum;
        const float stored = (encoding == TextureEncoding::Srgb && !is_alpha) ? linearToSrgb(mean) : mean;
        o[x * channels + c] = static_cast<uchar>(std::lround(255.0f * std::clamp(stored, 0.0f, 1.0f)));
      }
    }
  }
  return out;
}

}  // namespace

Texture::Texture(cv::Mat image, TextureSampler texture_sampler, TextureEncoding texture_encoding)
    : sampler(texture_sampler), encoding(texture_encoding) {
  levels.push_back(std::move(image));
  if (levels.front().empty()) return;
  // Each level is the mean of the light of the texels it covers: averaged in linear light, stored
  // in the texture's own encoding (8-bit sRGB keeps the dark steps a linear byte would lose).
  while (levels.back().cols > 1 || levels.back().rows > 1)
    levels.push_back(halveLevel(levels.back(), encoding));
}

vec4 sampleTexture(const Texture& texture, vec2 uv, float footprint) {
  if (texture.empty()) return vec4(1.0f);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = vec2(0.0f);
  if (!std::isfinite(footprint)) footprint = 0.0f;
  const TextureSampler& s = texture.sampler;
  const DecodeTable& decode = decodeTable(texture.encoding);
  const cv::Mat& base = texture.image();
  // Level of detail: log2 of the texels of level 0 one pixel covers; <= 0 means magnification.
  const float texels = footprint * static_cast<float>(std::max(base.cols, base.rows));
  const float lod = texels > 1.0f ? std::log2(texels) : 0.0f;
  if (lod <= 0.0f) return sampleLevel(base, s, uv, s.magnify_linear, decode);
  if (!s.use_mips) return sampleLevel(base, s, uv, s.minify_linear, decode);
  const float top = static_cast<float>(texture.levels.size() - 1);
  const float level = std::min(lod, top);
  if (!s.blend_mips) {
    const auto nearest = static_cast<std::size_t>(std::lround(level));
    return sampleLevel(texture.levels[nearest], s, uv, s.minify_linear, decode);
  }
  const auto lo = static_cast<std::size_t>(std::floor(level));
  const std::size_t hi = std::min(lo + 1, texture.levels.size() - 1);
  const float t = level - static_cast<float>(lo);
  return glm::mix(sampleLevel(texture.levels[lo], s, uv, s.minify_linear, decode),
                  sampleLevel(texture.levels[hi], s, uv, s.minify_linear, decode), t);
}

}  // namespace holo
