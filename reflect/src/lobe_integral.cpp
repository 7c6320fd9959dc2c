#include "holo/reflect/lobe_integral.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "holo/core/equirect.hpp"

namespace holo::reflect {

namespace {
constexpr int kCoarsestHeight = 4;
}  // namespace

GgxLobeIntegral::GgxLobeIntegral(const cv::Mat& pano, float yaw, LobeQuadratureOptions options)
    : options_(options) {
  if (pano.empty()) return;
  const int w = pano.cols, h = pano.rows;
  Level base;
  base.width = w;
  base.height = h;
  base.extent = std::max(2.0f * kPi / float(w), kPi / float(h));
  base.pixels.resize(std::size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    const double c0 = std::cos(double(y) / h * kPi), c1 = std::cos(double(y + 1) / h * kPi);
    const double omega = (2.0 * kPi / w) * (c0 - c1);
    // The solid-angle centroid's colatitude: where cos(theta) is halfway.
    const float v = float(std::acos(0.5 * (c0 + c1)) / kPi);
    for (int x = 0; x < w; ++x) {
      const vec3 c = equirect::uvToDirection({(float(x) + 0.5f) / float(w), v}, yaw);
      base.pixels[std::size_t(y) * w + x] = {c, float(omega), c, rgbAt(pano, x, y) * float(omega)};
    }
  }
  levels_.push_back(std::move(base));
  while (levels_.back().height > kCoarsestHeight && levels_.back().width > 2 * kCoarsestHeight) {
    const Level& fine = levels_.back();
    Level coarse;
    coarse.width = (fine.width + 1) / 2;
    coarse.height = (fine.height + 1) / 2;
    coarse.extent = 2.0f * fine.extent;
    coarse.pixels.resize(std::size_t(coarse.width) * coarse.height);
    for (int y = 0; y < coarse.height; ++y)
      for (int x = 0; x < coarse.width; ++x) {
        glm::dvec3 centroid(0.0), power_dir(0.0), power(0.0);
        double omega = 0.0;
        for (int j = 2 * y; j < std::min(2 * y + 2, fine.height); ++j)
          for (int i = 2 * x; i < std::min(2 * x + 2, fine.width); ++i) {
            const Pixel& p = fine.pixels[std::size_t(j) * fine.width + i];
            centroid += glm::dvec3(p.centroid) * double(p.omega);
            power_dir += glm::dvec3(p.power_dir) * double(luminance(p.power));
            power += glm::dvec3(p.power);
            omega += p.omega;
          }
        const vec3 c = vec3(glm::normalize(centroid));
        const vec3 pd = glm::length(power_dir) > 0.0 ? vec3(glm::normalize(power_dir)) : c;
        coarse.pixels[std::size_t(y) * coarse.width + x] = {c, float(omega), pd, vec3(power)};
      }
    levels_.push_back(std::move(coarse));
  }
}

GgxLobeIntegral::Lobe GgxLobeIntegral::lobe(float alpha) const {
  Lobe lobe;
  lobe.k1 = ggxLobeK1(alpha);
  lobe.split_cos.assign(levels_.size(), 2.0f);
  const float core = options_.core_ratio * alpha;
  lobe.finest = 0;
  while (lobe.finest + 1 < levelCount() && levels_[std::size_t(lobe.finest + 1)].extent <= core)
    ++lobe.finest;
  for (int k = lobe.finest + 1; k < levelCount(); ++k) {
    // Split near pixels (the tail rule) and any pixel overlapping the lobe's core (about 2 alpha
    // radians), where the weight does not fall as angle^-4 and coarse pixels would blur it.
    const float extent = levels_[std::size_t(k)].extent;
    const float reach = std::max(options_.tail_ratio * extent, 2.0f * alpha + extent);
    lobe.split_cos[std::size_t(k)] = reach >= kPi ? -2.0f : std::cos(reach);
  }
  return lobe;
}

vec3 GgxLobeIntegral::integrate(const vec3& n, const Lobe& lobe) const {
  if (levels_.empty()) return vec3(0.0f);
  const auto weight = [k1 = lobe.k1](float cos_nl) { return ggxLobeWeight(cos_nl, k1); };
  vec3 sum(0.0f);
  float norm = 0.0f;
  struct Item {
    int level, x, y;
  };
  std::array<Item, 128> stack;
  const int top = levelCount() - 1;
  const Level& coarsest = levels_[std::size_t(top)];
  for (int ty = 0; ty < coarsest.height; ++ty)
    for (int tx = 0; tx < coarsest.width; ++tx) {
      int depth = 0;
      stack[std::size_t(depth++)] = {top, tx, ty};
      while (depth > 0) {
        const Item it = stack[std::size_t(--depth)];
        const Level& lv = levels_[std::size_t(it.level)];
        const Pixel& p = lv.pixels[std::size_t(it.y) * lv.width + it.x];
        const float c = glm::dot(n, p.centroid);
        if (c > lobe.split_cos[std::size_t(it.level)]) {
          const Level& fine = levels_[std::size_t(it.level - 1)];
          for (int j = 2 * it.y; j < std::min(2 * it.y + 2, fine.height); ++j)
            for (int i = 2 * it.x; i < std::min(2 * it.x + 2, fine.width); ++i)
              stack[std::size_t(depth++)] = {it.level - 1, i, j};
          continue;
        }
        const float wc = weight(c);
        norm += wc * p.omega;
        // A panorama pixel's radiance is constant over it: its power centroid is its centroid.
        sum += (it.level == 0 ? wc : weight(glm::dot(n, p.power_dir))) * p.power;
      }
    }
  return norm > 0.0f ? sum / norm : vec3(0.0f);
}

}  // namespace holo::reflect
