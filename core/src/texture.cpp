#include "holo/core/texture.hpp"

#include <algorithm>
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

vec4 texelAt(const cv::Mat& level, int x, int y) {
  const uchar* p = level.ptr<uchar>(y) + x * level.channels();
  const float a = level.channels() == 4 ? p[3] / 255.0f : 1.0f;
  return {p[2] / 255.0f, p[1] / 255.0f, p[0] / 255.0f, a};
}

// One level, texel centres at half-integers (glTF and OpenGL convention).
vec4 sampleLevel(const cv::Mat& level, const TextureSampler& s, vec2 uv, bool linear) {
  const float x = reduce(uv.x, s.wrap_u) * static_cast<float>(level.cols);
  const float y = reduce(uv.y, s.wrap_v) * static_cast<float>(level.rows);
  if (!linear) {
    return texelAt(level, wrapIndex(static_cast<int>(std::floor(x)), level.cols, s.wrap_u),
                   wrapIndex(static_cast<int>(std::floor(y)), level.rows, s.wrap_v));
  }
  const float fx = x - 0.5f, fy = y - 0.5f;
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float tx = fx - x0f, ty = fy - y0f;
  const int x0 = static_cast<int>(x0f), y0 = static_cast<int>(y0f);
  const int xa = wrapIndex(x0, level.cols, s.wrap_u), xb = wrapIndex(x0 + 1, level.cols, s.wrap_u);
  const int ya = wrapIndex(y0, level.rows, s.wrap_v), yb = wrapIndex(y0 + 1, level.rows, s.wrap_v);
  const vec4 top = glm::mix(texelAt(level, xa, ya), texelAt(level, xb, ya), tx);
  const vec4 bottom = glm::mix(texelAt(level, xa, yb), texelAt(level, xb, yb), tx);
  return glm::mix(top, bottom, ty);
}

}  // namespace

Texture::Texture(cv::Mat image, TextureSampler texture_sampler) : sampler(texture_sampler) {
  levels.push_back(std::move(image));
  if (levels.front().empty()) return;
  while (levels.back().cols > 1 || levels.back().rows > 1) {
    const cv::Mat& last = levels.back();
    const cv::Size half((last.cols + 1) / 2, (last.rows + 1) / 2);
    cv::Mat next;
    cv::resize(last, next, half, 0, 0, cv::INTER_AREA);
    levels.push_back(std::move(next));
  }
}

vec4 sampleTexture(const Texture& texture, vec2 uv, float footprint) {
  if (texture.empty()) return vec4(1.0f);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = vec2(0.0f);
  if (!std::isfinite(footprint)) footprint = 0.0f;
  const TextureSampler& s = texture.sampler;
  const cv::Mat& base = texture.image();
  // Level of detail: log2 of the texels of level 0 one pixel covers; <= 0 means magnification.
  const float texels = footprint * static_cast<float>(std::max(base.cols, base.rows));
  const float lod = texels > 1.0f ? std::log2(texels) : 0.0f;
  if (lod <= 0.0f) return sampleLevel(base, s, uv, s.magnify_linear);
  if (!s.use_mips) return sampleLevel(base, s, uv, s.minify_linear);
  const float top = static_cast<float>(texture.levels.size() - 1);
  const float level = std::min(lod, top);
  if (!s.blend_mips) {
    const auto nearest = static_cast<std::size_t>(std::lround(level));
    return sampleLevel(texture.levels[nearest], s, uv, s.minify_linear);
  }
  const auto lo = static_cast<std::size_t>(std::floor(level));
  const std::size_t hi = std::min(lo + 1, texture.levels.size() - 1);
  const float t = level - static_cast<float>(lo);
  return glm::mix(sampleLevel(texture.levels[lo], s, uv, s.minify_linear),
                  sampleLevel(texture.levels[hi], s, uv, s.minify_linear), t);
}

}  // namespace holo
