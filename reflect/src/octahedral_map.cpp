#include "holo/reflect/octahedral_map.hpp"

#include <algorithm>
#include <cmath>

namespace holo::reflect {

namespace {
float signNotZero(float v) {
  return v >= 0.0f ? 1.0f : -1.0f;
}
}  // namespace

vec2 octahedralEncode(const vec3& d) {
  const float l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
  if (!(l1 > 0.0f)) return {0.5f, 0.5f};
  vec2 p(d.x / l1, d.z / l1);
  if (d.y < 0.0f) {
    p = vec2((1.0f - std::abs(p.y)) * signNotZero(p.x), (1.0f - std::abs(p.x)) * signNotZero(p.y));
  }
  return glm::clamp(p * 0.5f + 0.5f, vec2(0.0f), vec2(1.0f));
}

vec3 octahedralDecode(const vec2& uv) {
  const vec2 p = uv * 2.0f - 1.0f;
  vec3 d(p.x, 1.0f - std::abs(p.x) - std::abs(p.y), p.y);
  if (d.y < 0.0f) {
    const float x = d.x;
    d.x = (1.0f - std::abs(d.z)) * signNotZero(x);
    d.z = (1.0f - std::abs(x)) * signNotZero(d.z);
  }
  return glm::normalize(d);
}

const vec3& OctahedralMap::wrapped(int x, int y) const {
  // Crossing an edge of the square mirrors along that edge (edges fold onto themselves).
  if (x < 0) {
    x = -x - 1;
    y = size_ - 1 - y;
  } else if (x >= size_) {
    x = 2 * size_ - 1 - x;
    y = size_ - 1 - y;
  }
  if (y < 0) {
    y = -y - 1;
    x = size_ - 1 - x;
  } else if (y >= size_) {
    y = 2 * size_ - 1 - y;
    x = size_ - 1 - x;
  }
  return at(std::clamp(x, 0, size_ - 1), std::clamp(y, 0, size_ - 1));
}

vec3 OctahedralMap::texelDirection(int x, int y) const {
  return octahedralDecode({(float(x) + 0.5f) / float(size_), (float(y) + 0.5f) / float(size_)});
}

vec3 OctahedralMap::bilinear(const vec3& direction) const {
  return bilinearAt(octahedralEncode(direction));
}

vec3 OctahedralMap::bilinearAt(const vec2& uv) const {
  if (size_ == 0) return vec3(0.0f);
  const float fx = uv.x * float(size_) - 0.5f, fy = uv.y * float(size_) - 0.5f;
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const float tx = fx - float(x0), ty = fy - float(y0);
  if (x0 >= 0 && y0 >= 0 && x0 + 1 < size_ && y0 + 1 < size_) {  // all four inside: no folding
    const vec3* row0 = &texels_[std::size_t(y0) * std::size_t(size_) + std::size_t(x0)];
    const vec3* row1 = row0 + size_;
    return (1 - ty) * ((1 - tx) * row0[0] + tx * row0[1]) + ty * ((1 - tx) * row1[0] + tx * row1[1]);
  }
  return (1 - ty) * ((1 - tx) * wrapped(x0, y0) + tx * wrapped(x0 + 1, y0)) +
         ty * ((1 - tx) * wrapped(x0, y0 + 1) + tx * wrapped(x0 + 1, y0 + 1));
}

OctahedralMap OctahedralMap::downsampled() const {
  OctahedralMap out(std::max(1, size_ / 2));
  for (int y = 0; y < out.size_; ++y)
    for (int x = 0; x < out.size_; ++x)
      out.at(x, y) =
          0.25f * (at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1));
  return out;
}

}  // namespace holo::reflect
