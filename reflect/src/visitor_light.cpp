#include "holo/reflect/visitor_light.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "equirect_disc.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/effect_plan.hpp"
#include "holo/reflect/irradiance_sh.hpp"
#include "holo/reflect/tone_map.hpp"
#include "sphere_texels.hpp"

namespace holo::reflect {
namespace {

// The hall's radiance a probe texel stands for, read at a lobe about a 64-wide texel's size.
constexpr float kHallReadRoughness = 0.25f;

vec3 probePosition(const Bounds3& box, int probe) {
  return vec3((probe & 1) ? box.hi.x : box.lo.x, (probe & 2) ? box.hi.y : box.lo.y,
              (probe & 4) ? box.hi.z : box.lo.z);
}

}  // namespace

VisitorLight::VisitorLight(int map_width) : width_(map_width), height_(map_width / 2) {
  if (map_width < 8 || map_width % 2 != 0 || map_width > 1024)
    throw InputError("visitor light", "map_width", "an even number of texels in 8..1024",
                     std::to_string(map_width));
  SphereTexels texels = sphereTexels(width_, height_);
  direction_ = std::move(texels.direction);
  solid_angle_ = std::move(texels.solid_angle);
}

void VisitorLight::build(const VoxelGrid& grid, const PrefilteredIbl& ibl, const Bounds3& relic_bounds) {
  coefficients_ = {};
  splats_ = 0;
  covered_texels_ = 0;
  empty_ = grid.empty() || relic_bounds.empty();
  if (empty_) return;
  box_ = relic_bounds;
  // The occupied voxels' centres and samples, gathered once for the eight probes.
  struct Voxel {
    vec3 centre;
    vec3 premultiplied;  // radiance * w
    float weight;        // w
  };
  std::vector<Voxel> voxels;
  voxels.reserve(grid.occupiedCount());
  grid.forEachOccupied([&](const glm::ivec3& v, const VoxelSample& s) {
    if (!isFinite(s.radiance) || !std::isfinite(s.weight)) return;  // must not poison the sums
    const float w = std::clamp(s.weight, 0.0f, 1.0f);
    if (!(w > 0.0f)) return;
    const Bounds3 box = grid.voxelBounds(v);
    voxels.push_back({0.5f * (box.lo + box.hi), glm::max(s.radiance, vec3(0.0f)) * w, w});
  });
  const std::size_t n = direction_.size();
  std::atomic<std::uint64_t> splats{0}, covered{0};
  tbb::parallel_for(0, kProbes, [&](int probe) {
    const vec3 origin = probePosition(box_, probe);
    std::vector<float> depth(n, std::numeric_limits<float>::infinity());
    std::vector<std::int32_t> nearest(n, -1);
    std::uint64_t local_splats = 0;
    for (std::size_t k = 0; k < voxels.size(); ++k) {
      const vec3 d = voxels[k].centre - origin;
      const float dist = glm::length(d);
      if (!(dist > grid.voxelSize())) continue;  // the probe inside a visitor: no direction to it
      // A disc of one voxel edge's angular radius: neighbouring voxels close up.
      forEachDiscPixel(d / dist, std::atan(grid.voxelSize() / dist), width_, height_, 0.0f,
                       [&](int tx, int ty) {
                         const std::size_t t = std::size_t(ty) * std::size_t(width_) + std::size_t(tx);
                         ++local_splats;
                         if (dist >= depth[t]) return;
                         depth[t] = dist;
                         nearest[t] = std::int32_t(k);
                       });
    }
    Coefficients c{};
    std::uint64_t local_covered = 0;
    for (std::size_t t = 0; t < n; ++t) {
      if (nearest[t] < 0) continue;
      ++local_covered;
      const Voxel& v = voxels[std::size_t(nearest[t])];
      const vec3 hall = ibl.seenFrom(origin, direction_[t], kHallReadRoughness);
      const vec3 change = (v.premultiplied - v.weight * hall) * solid_angle_[t];
      const auto y = IrradianceSH::basis(direction_[t]);
      for (int i = 0; i < 9; ++i) c[std::size_t(i)] += y[std::size_t(i)] * change;
    }
    Response& packed = coefficients_[std::size_t(probe)];
    for (std::size_t i = 0; i < 9; ++i)
      for (int ch = 0; ch < 3; ++ch) packed[3 * i + std::size_t(ch)] = c[i][ch];
    splats += local_splats;
    covered += local_covered;
  });
  splats_ = splats;
  covered_texels_ = covered;
}

namespace {

// The bands 0-2 clamped-cosine kernel: the irradiance a normal at cosine c from a unit of radiance
// x solid angle gets, sum over l of A_l (2l + 1) / (4 pi) P_l(c).
float cosineKernel(float c) {
  const float a0 = IrradianceSH::kCosineLobe[0], a1 = IrradianceSH::kCosineLobe[1],
              a2 = IrradianceSH::kCosineLobe[4];
  return (a0 + 3.0f * a1 * c + 5.0f * a2 * 0.5f * (3.0f * c * c - 1.0f)) / (4.0f * kPi);
}

// Its integral's magnitude over the sphere, 2 pi int_{-1}^{1} |K(c)| dc: the most irradiance a
// change of radiance at most 1 in every direction can make (pi in front, a little ringing behind).
float kernelSphereIntegral() {
  constexpr int kSteps = 4096;
  double sum = 0.0;
  for (int i = 0; i < kSteps; ++i)
    sum += std::abs(cosineKernel(-1.0f + 2.0f * (float(i) + 0.5f) / float(kSteps)));
  return float(2.0 * double(kPi) * sum * 2.0 / double(kSteps));
}

}  // namespace

float VisitorLight::cosinePeak() {
  return cosineKernel(1.0f);
}

float VisitorLight::largestRadianceChange(const VoxelGrid& grid, const Bounds3& relic_bounds,
                                          const vec3& brightest_hall, bool wide_lobes) {
  if (grid.empty() || relic_bounds.empty()) return 0.0f;
  const float edge = grid.voxelSize();
  vec3 integral(0.0f), largest(0.0f);  // of |dL| over the sphere, and its largest value
  grid.forEachOccupied([&](const glm::ivec3& v, const VoxelSample& s) {
    const float w = std::clamp(s.weight, 0.0f, 1.0f);
    if (!(w > 0.0f) || !isFinite(s.radiance)) return;
    const Bounds3 box = grid.voxelBounds(v);
    const vec3 centre = 0.5f * (box.lo + box.hi);
    const vec3 gap = glm::max(glm::max(relic_bounds.lo - centre, centre - relic_bounds.hi), vec3(0.0f));
    const float d = glm::length(gap);
    // The disc of angular radius atan(edge / d): 2 pi (1 - cos); a hemisphere where d is 0.
    const float solid_angle = 2.0f * kPi * (1.0f - d / std::sqrt(d * d + edge * edge));
    const vec3 change = w * glm::max(glm::max(s.radiance, vec3(0.0f)), brightest_hall);
    integral += solid_angle * change;
    largest = glm::max(largest, change);
  });
  static const float whole_sphere = kernelSphereIntegral();
  const vec3 irradiance = glm::min(cosinePeak() * integral, whole_sphere * largest);
  return maxComponent(irradiance) / kPi * (wide_lobes ? 2.0f : 1.0f);
}

VisitorLight::Coefficients VisitorLight::coefficientsAt(const vec3& position) const {
  const vec3 extent = box_.hi - box_.lo;
  vec3 f(0.5f);
  for (int a = 0; a < 3; ++a)
    if (extent[a] > 0.0f) f[a] = std::clamp((position[a] - box_.lo[a]) / extent[a], 0.0f, 1.0f);
  Coefficients c{};
  for (int probe = 0; probe < kProbes; ++probe) {
    const float w = ((probe & 1) ? f.x : 1.0f - f.x) * ((probe & 2) ? f.y : 1.0f - f.y) *
                    ((probe & 4) ? f.z : 1.0f - f.z);
    const Response& from = coefficients_[std::size_t(probe)];
    for (std::size_t i = 0; i < 9; ++i)
      for (int ch = 0; ch < 3; ++ch) c[i][ch] += w * from[3 * i + std::size_t(ch)];
  }
  return c;
}

namespace {

// kCosineLobe_i Y_i(direction): the clamped-cosine convolution's weights of the 9 coefficients.
std::array<float, 9> cosineLobe(const vec3& direction) {
  const auto y = IrradianceSH::basis(direction);
  std::array<float, 9> lobe{};
  for (std::size_t i = 0; i < 9; ++i) lobe[i] = IrradianceSH::kCosineLobe[i] * y[i];
  return lobe;
}

vec3 convolve(const std::array<vec3, 9>& c, const std::array<float, 9>& lobe) {
  vec3 e(0.0f);
  for (std::size_t i = 0; i < 9; ++i) e += lobe[i] * c[i];
  return e;
}

}  // namespace

vec3 VisitorLight::irradianceChange(const vec3& position, const vec3& normal) const {
  if (empty_) return vec3(0.0f);
  return convolve(coefficientsAt(position), cosineLobe(normal));
}

VisitorLight::Receivers VisitorLight::receivers(const HitPointBuffer& hits,
                                                const std::vector<SplitSumShading>& shading,
                                                const PrefilteredIbl& ibl) {
  Receivers out;
  const std::size_t n = hits.covered.size();
  out.pixels = hits.covered;
  out.positions.resize(n);
  out.responses.resize(n);
  std::atomic<std::uint64_t> samples{0};
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
        std::uint64_t local = 0;
        for (std::size_t k = r.begin(); k < r.end(); ++k) {
          const std::size_t p = hits.covered[k];
          const std::size_t first = hits.firstSample(p);
          const int count = hits.sampleCount(p);
          Response& response = out.responses[k];
          response.fill(0.0f);
          bool positioned = false;
          for (std::size_t i = first; i < first + std::size_t(count); ++i) {
            if (!hits.valid[i]) continue;
            const HitPoint& hp = hits.hits[i];
            if (!positioned) out.positions[k] = hp.position;
            positioned = true;
            ++local;
            // The diffuse reflectance times the visibility's share of the hall's light, per channel.
            vec3 rho(0.0f);
            const vec3 hall = ibl.irradiance(hp.normal);
            for (int ch = 0; ch < 3; ++ch)
              if (hall[ch] > 1e-6f) rho[ch] = std::clamp(shading[i].diffuse[ch] / hall[ch], 0.0f, 1.0f / kPi);
            const auto normal_lobe = IrradianceSH::basis(hp.normal);
            for (std::size_t c = 0; c < 9; ++c)
              for (int ch = 0; ch < 3; ++ch)
                response[3 * c + std::size_t(ch)] += rho[ch] * IrradianceSH::kCosineLobe[c] * normal_lobe[c];
            if (hp.material.roughness >= kGlossyRoughnessLimit) {
              const vec3 specular = shading[i].specular_scale / kPi;
              const auto reflected_lobe = IrradianceSH::basis(hp.reflected);
              for (std::size_t c = 0; c < 9; ++c)
                for (int ch = 0; ch < 3; ++ch)
                  response[3 * c + std::size_t(ch)] +=
                      specular[ch] * IrradianceSH::kCosineLobe[c] * reflected_lobe[c];
            }
          }
          for (float& v : response) v /= float(count);
        }
        samples += local;
      });
  out.samples = samples;
  return out;
}

vec3 VisitorLight::responseChange(const vec3& position, const Response& response) const {
  const vec3 extent = box_.hi - box_.lo;
  vec3 f(0.5f);
  for (int a = 0; a < 3; ++a)
    if (extent[a] > 0.0f) f[a] = std::clamp((position[a] - box_.lo[a]) / extent[a], 0.0f, 1.0f);
  std::array<float, kProbes> weight;
  for (int probe = 0; probe < kProbes; ++probe)
    weight[std::size_t(probe)] = ((probe & 1) ? f.x : 1.0f - f.x) * ((probe & 2) ? f.y : 1.0f - f.y) *
                                 ((probe & 4) ? f.z : 1.0f - f.z);
  // Runs of 28 floats (whole SIMD vectors, the compiler's): the interpolated coefficients times the
  // response, then summed per channel, the channels repeating every 3 floats (12 = 4 x 3).
  Response product{};
  for (std::size_t probe = 0; probe < std::size_t(kProbes); ++probe)
    for (std::size_t k = 0; k < product.size(); ++k) product[k] += weight[probe] * coefficients_[probe][k];
  for (std::size_t k = 0; k < product.size(); ++k) product[k] *= response[k];
  std::array<float, 12> fold{};
  for (std::size_t k = 0; k < 12; ++k) fold[k] = product[k] + product[12 + k];
  for (std::size_t k = 0; k < 4; ++k) fold[k] += product[24 + k];
  vec3 change(0.0f);
  for (std::size_t k = 0; k < 12; ++k) change[int(k % 3)] += fold[k];
  return change;
}

std::uint64_t VisitorLight::apply(const Receivers& receivers, int width, cv::Mat& hdr, cv::Mat* display,
                                  float exposure) const {
  if (empty_) return 0;
  const std::size_t w = std::size_t(width);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, receivers.pixels.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t p = receivers.pixels[k];
                        const int x = int(p % w), y = int(p / w);
                        const vec3 changed = glm::max(
                            rgbAt(hdr, x, y) + responseChange(receivers.positions[k], receivers.responses[k]),
                            vec3(0.0f));
                        setRgb(hdr, x, y, changed);
                        if (display) display->at<cv::Vec3b>(y, x) = toneMapPixel(changed, exposure);
                      }
                    });
  return receivers.samples;
}

}  // namespace holo::reflect
