#include "holo/reflect/rough_foreground_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "equirect_disc.hpp"
#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/reflect/lobe_integral.hpp"
#include "sphere_texels.hpp"

namespace holo::reflect {

RoughForegroundMap::RoughForegroundMap(int width, std::vector<float> roughness)
    : width_(width), height_(width / 2), roughness_(std::move(roughness)) {
  if (width < 8 || width % 2 != 0 || width > 1024)
    throw InputError("rough foreground map", "width", "an even number of texels in 8..1024",
                     std::to_string(width));
  if (roughness_.empty() || roughness_.size() > 8)
    throw InputError("rough foreground map", "roughness", "1..8 values", std::to_string(roughness_.size()));
  for (float& r : roughness_) {
    r = std::isfinite(r) ? std::clamp(r, 0.05f, 1.0f) : 1.0f;
    k1_.push_back(ggxLobeK1(r * r));
  }
  SphereTexels texels = sphereTexels(width_, height_);
  direction_ = std::move(texels.direction);
  solid_angle_ = std::move(texels.solid_angle);
  const std::size_t n = direction_.size();
  for (const float k1 : k1_) {
    std::vector<float> norm(n, 0.0f);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t o) {
      double sum = 0.0;
      for (std::size_t i = 0; i < n; ++i)
        sum += double(ggxLobeWeight(glm::dot(direction_[o], direction_[i]), k1)) * double(solid_angle_[i]);
      norm[o] = float(sum);
    });
    norm_.push_back(std::move(norm));
  }
  splat_.resize(n);
  depth_.resize(n);
  filtered_.assign(roughness_.size(), std::vector<Texel>(n));
}

void RoughForegroundMap::build(const VoxelGrid& grid, const vec3& centre) {
  std::fill(splat_.begin(), splat_.end(), Texel{});
  std::fill(depth_.begin(), depth_.end(), std::numeric_limits<float>::infinity());
  covered_.clear();
  if (!grid.empty()) {
    grid.forEachOccupied([&](const glm::ivec3& v, const VoxelSample& s) {
      const Bounds3 box = grid.voxelBounds(v);
      const vec3 d = 0.5f * (box.lo + box.hi) - centre;
      const float dist = glm::length(d);
      if (!(dist > 1e-6f)) return;
      if (!isFinite(s.radiance) || !std::isfinite(s.weight)) return;  // must not poison the map
      const float weight = std::clamp(s.weight, 0.0f, 1.0f);
      const Texel texel{glm::max(s.radiance, vec3(0.0f)) * weight, weight};
      // A disc of one voxel edge's angular radius: neighbouring voxels close up.
      forEachDiscPixel(d / dist, std::atan(grid.voxelSize() / dist), width_, height_, 0.0f,
                       [&](int tx, int ty) {
                         const std::size_t t = std::size_t(ty) * std::size_t(width_) + std::size_t(tx);
                         if (dist >= depth_[t]) return;
                         depth_[t] = dist;
                         splat_[t] = texel;
                       });
    });
    for (std::size_t t = 0; t < splat_.size(); ++t)
      if (splat_[t].weight > 0.0f) covered_.push_back(std::uint32_t(t));
  }
  for (std::size_t k = 0; k < roughness_.size(); ++k) {
    const float k1 = k1_[k];
    std::vector<Texel>& out = filtered_[k];
    const std::vector<float>& norm = norm_[k];
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, out.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t o = r.begin(); o < r.end(); ++o) {
            Texel sum;
            for (const std::uint32_t i : covered_) {
              const float w = ggxLobeWeight(glm::dot(direction_[o], direction_[i]), k1) * solid_angle_[i];
              sum.premultiplied += w * splat_[i].premultiplied;
              sum.weight += w * splat_[i].weight;
            }
            const float inv = norm[o] > 0.0f ? 1.0f / norm[o] : 0.0f;
            out[o] = {sum.premultiplied * inv, std::clamp(sum.weight * inv, 0.0f, 1.0f)};
          }
        });
  }
}

ForegroundSample RoughForegroundMap::lookup(const vec3& direction, float roughness) const {
  const float len = glm::length(direction);
  if (!(len > 1e-12f) || !isFinite(direction)) return {};
  std::size_t k = 0;
  for (std::size_t i = 1; i < roughness_.size(); ++i)
    if (std::abs(roughness_[i] - roughness) < std::abs(roughness_[k] - roughness)) k = i;
  const std::vector<Texel>& map = filtered_[k];
  const equirect::BilinearTaps taps =
      equirect::bilinearTaps(equirect::directionToUv(direction / len), width_, height_);
  Texel t;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const float w = (i ? taps.fx : 1.0f - taps.fx) * (j ? taps.fy : 1.0f - taps.fy);
      const Texel& s = map[std::size_t(taps.y[j]) * std::size_t(width_) + std::size_t(taps.x[i])];
      t.premultiplied += w * s.premultiplied;
      t.weight += w * s.weight;
    }
  ForegroundSample out;
  out.weight = std::clamp(t.weight, 0.0f, 1.0f);
  if (t.weight > 0.0f) out.radiance = t.premultiplied / t.weight;
  return out;
}

}  // namespace holo::reflect
