#include "holo/reflect/prefiltered_ibl.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/reflect/dfg_table.hpp"

namespace holo::reflect {

namespace {

int floorPow2(int v) {
  int p = 1;
  while (p * 2 <= v) p *= 2;
  return p;
}
int ceilPow2(int v) {
  int p = 1;
  while (p < v) p *= 2;
  return p;
}

// Level 0: every panorama pixel's radiance * solid angle lands in the octahedral texel of its
// centre (a box filter that keeps the total power exactly); the rare texel no pixel centre falls
// in (base finer than the panorama near the equator) takes the panorama's nearest pixel.
OctahedralMap resamplePanorama(const cv::Mat& pano, float yaw, int size) {
  const int w = pano.cols, h = pano.rows;
  std::vector<glm::dvec3> sum(std::size_t(size) * size, glm::dvec3(0.0));
  std::vector<double> weight(std::size_t(size) * size, 0.0);
  for (int y = 0; y < h; ++y) {
    const double omega = Environment::pixelSolidAngle(y, w, h);
    for (int x = 0; x < w; ++x) {
      const vec3 d =
          equirect::uvToDirection({(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)}, yaw);
      const vec2 uv = octahedralEncode(d);
      const int tx = std::clamp(int(uv.x * float(size)), 0, size - 1);
      const int ty = std::clamp(int(uv.y * float(size)), 0, size - 1);
      const std::size_t i = std::size_t(ty) * size + tx;
      sum[i] += glm::dvec3(rgbAt(pano, x, y)) * omega;
      weight[i] += omega;
    }
  }
  OctahedralMap map(size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const std::size_t i = std::size_t(y) * size + x;
      if (weight[i] > 0) {
        map.at(x, y) = vec3(sum[i] / weight[i]);
      } else {
        const vec2 uv = equirect::directionToUv(map.texelDirection(x, y), yaw);
        map.at(x, y) = rgbAt(pano, std::clamp(int(uv.x * float(w)), 0, w - 1),
                             std::clamp(int(uv.y * float(h)), 0, h - 1));
      }
    }
  return map;
}

// The panorama's few very bright pixels (a sun, a lamp), which a sample-based prefilter would
// either miss or, read from a blurred MIP level, smear across the horizon. They are taken out of
// the panorama and integrated exactly for every texel (2 x 2 point lights per pixel).
struct BrightLight {
  vec3 direction;
  vec3 power;  // radiance * solid angle / 4 (one of the 4 sub-points), RGB
};
constexpr int kMaxBrightPixels = 512;
constexpr float kBrightFactor = 32.0f;  // "bright" = luminance above 32 x the sphere's mean

std::vector<BrightLight> extractBrightPixels(cv::Mat& pano, float yaw, const vec3& integral) {
  const int w = pano.cols, h = pano.rows;
  const float threshold = kBrightFactor * luminance(integral) / (4.0f * kPi);
  struct Candidate {
    double power;
    int x, y;
  };
  std::vector<Candidate> candidates;
  for (int y = 0; y < h; ++y) {
    const double omega = Environment::pixelSolidAngle(y, w, h);
    for (int x = 0; x < w; ++x) {
      const float lum = luminance(rgbAt(pano, x, y));
      if (threshold > 0.0f && lum > threshold) candidates.push_back({lum * omega, x, y});
    }
  }
  if (candidates.size() > std::size_t(kMaxBrightPixels)) {
    std::nth_element(candidates.begin(), candidates.begin() + kMaxBrightPixels, candidates.end(),
                     [](const Candidate& a, const Candidate& b) { return a.power > b.power; });
    candidates.resize(std::size_t(kMaxBrightPixels));
  }
  std::vector<BrightLight> lights;
  for (const Candidate& c : candidates) {
    const vec3 radiance = rgbAt(pano, c.x, c.y);
    const float quarter = float(Environment::pixelSolidAngle(c.y, w, h)) * 0.25f;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        lights.push_back({equirect::uvToDirection({(float(c.x) + 0.25f + 0.5f * float(i)) / float(w),
                                                   (float(c.y) + 0.25f + 0.5f * float(j)) / float(h)},
                                                  yaw),
                          radiance * quarter});
    setRgb(pano, c.x, c.y, vec3(0.0f));
  }
  return lights;
}

// The prefilter's lobe weight W(l) = pdf(l) * n.l with n = v: pdf(l) = D(h) / 4, n.h =
// sqrt((1 + n.l) / 2).
float lobeWeight(float n_dot_l, float alpha) {
  if (n_dot_l <= 0.0f) return 0.0f;
  return ggx::D(std::sqrt(0.5f * (1.0f + n_dot_l)), alpha) * 0.25f * n_dot_l;
}

vec3 trilinear(const std::vector<OctahedralMap>& chain, const vec3& d, float lod) {
  const float l = std::clamp(lod, 0.0f, float(chain.size() - 1));
  const int l0 = std::min(int(l), int(chain.size()) - 1);
  const int l1 = std::min(l0 + 1, int(chain.size()) - 1);
  const float t = l - float(l0);
  const vec3 a = chain[std::size_t(l0)].bilinear(d);
  if (t <= 0.0f || l1 == l0) return a;
  return (1.0f - t) * a + t * chain[std::size_t(l1)].bilinear(d);
}

float hammersley(std::uint32_t i) {
  i = (i << 16u) | (i >> 16u);
  i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
  i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
  i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
  i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
  return float(i) * 2.3283064365386963e-10f;
}

struct LobeSample {
  vec3 l;     // local direction (normal = view = +Z)
  float nol;  // weight
  float lod;  // source MIP level
};

std::vector<LobeSample> lobeSamples(float alpha, int count, int base_size, float lod_bias) {
  std::vector<LobeSample> out;
  const float omega_p = 4.0f * kPi / float(base_size * base_size);
  for (int k = 0; k < count; ++k) {
    const vec2 u((float(k) + 0.5f) / float(count), hammersley(std::uint32_t(k)));
    const vec3 hv = ggx::sampleNormal(alpha, u);
    const vec3 l = 2.0f * hv.z * hv - vec3(0, 0, 1);
    if (l.z <= 0.0f) continue;
    // pdf of l with n = v: D(h) (n.h) / (4 v.h) = D(h) / 4.
    const float pdf = ggx::D(hv.z, alpha) * 0.25f;
    const float omega_s = 1.0f / (float(count) * std::max(pdf, 1e-20f));
    const float lod = std::max(0.0f, 0.5f * std::log2(omega_s / omega_p) + lod_bias);
    out.push_back({l, l.z, lod});
  }
  return out;
}

// Integral of the lobe weight over the sphere (the FIS estimate's denominator), by 4096
// Hammersley samples of the lobe's own distribution.
double lobeNormalisation(float alpha) {
  constexpr int kSamples = 4096;
  double sum = 0;
  for (int k = 0; k < kSamples; ++k) {
    const vec3 hv = ggx::sampleNormal(alpha, {(float(k) + 0.5f) / kSamples, hammersley(std::uint32_t(k))});
    sum += std::max(0.0f, 2.0f * hv.z * hv.z - 1.0f);  // n.l
  }
  return sum / kSamples;
}

}  // namespace

PrefilteredIbl::PrefilteredIbl(const Environment& env, PrefilterOptions options)
    : sh_(env), source_hash_(env.contentHash()) {
  const int levels = std::max(2, options.levels);
  int base = options.base_size;
  if (base <= 0) base = std::clamp(floorPow2(std::max(1, env.panorama().cols / 4)), 16, 1024);
  base = floorPow2(std::max(base, 4));

  levels_.resize(std::size_t(levels));
  std::vector<OctahedralMap> chain;  // MIP chain of the panorama without its bright pixels
  std::vector<BrightLight> lights;
  if (env.panorama().empty()) {
    chain.emplace_back(base);
    levels_[0] = chain[0];
  } else {
    levels_[0] = resamplePanorama(env.panorama(), env.yaw(), base);
    cv::Mat residual = env.panorama().clone();
    lights = extractBrightPixels(residual, env.yaw(), env.integral());
    chain.push_back(lights.empty() ? levels_[0] : resamplePanorama(residual, env.yaw(), base));
  }
  while (chain.back().size() > 1) chain.push_back(chain.back().downsampled());

  for (int l = 1; l < levels; ++l) {
    const float roughness = levelRoughness(l);
    const float alpha = std::max(roughnessToAlpha(roughness), 1e-4f);
    // Texels about half the lobe's angular width (~2 alpha radians) wide; bilinear lookups
    // interpolate between them.
    const int size = std::clamp(ceilPow2(int(std::ceil(2.0f / alpha))), 16, base);
    const float bright_scale = lights.empty() ? 0.0f : float(1.0 / lobeNormalisation(alpha));
    const auto samples = lobeSamples(alpha, std::max(1, options.samples_per_texel), base, options.lod_bias);
    OctahedralMap& out = levels_[std::size_t(l)];
    out = OctahedralMap(size);
    tbb::parallel_for(tbb::blocked_range<int>(0, size), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < size; ++x) {
          const Frame frame(out.texelDirection(x, y));
          vec3 sum(0.0f);
          float wsum = 0.0f;
          for (const LobeSample& s : samples) {
            sum += s.nol * trilinear(chain, frame.toWorld(s.l), s.lod);
            wsum += s.nol;
          }
          vec3 texel = wsum > 0.0f ? sum / wsum : vec3(0.0f);
          vec3 bright(0.0f);
          for (const BrightLight& light : lights)
            bright += light.power * lobeWeight(glm::dot(frame.n, light.direction), alpha);
          out.at(x, y) = texel + bright * bright_scale;
        }
    });
  }
}

float PrefilteredIbl::levelRoughness(int level) const {
  return float(level) / float(std::max(1, levelCount() - 1));
}

vec3 PrefilteredIbl::specular(const vec3& direction, float roughness) const {
  if (levels_.empty()) return vec3(0.0f);
  const float l = std::clamp(roughness, 0.0f, 1.0f) * float(levelCount() - 1);
  const int l0 = std::min(int(l), levelCount() - 1);
  const int l1 = std::min(l0 + 1, levelCount() - 1);
  const float t = l - float(l0);
  const vec3 a = levels_[std::size_t(l0)].bilinear(direction);
  if (t <= 0.0f || l1 == l0) return a;
  return (1.0f - t) * a + t * levels_[std::size_t(l1)].bilinear(direction);
}

vec3 PrefilteredIbl::shade(const SurfaceMaterial& m, const vec3& n, const vec3& wo) const {
  const float nv = glm::dot(n, wo);
  if (!(nv > 0.0f)) return vec3(0.0f);
  const float metallic = std::clamp(m.metallic, 0.0f, 1.0f);
  const float s = std::clamp(m.specular, 0.0f, 1.0f);
  const vec3 base = glm::clamp(m.base_color, vec3(0.0f), vec3(1.0f));
  const vec2 ab = dfg(nv, m.roughness);
  const vec3 f0 = (1.0f - metallic) * kDielectricF0 * s + metallic * base;
  const float f90 = (1.0f - metallic) * s + metallic;
  const vec3 r = glm::reflect(-wo, n);
  const vec3 spec = specular(r, m.roughness) * (f0 * ab.x + f90 * ab.y);
  const float dielectric_reflectance = kDielectricF0 * s * ab.x + s * ab.y;
  const vec3 diffuse = (1.0f - metallic) * (1.0f - dielectric_reflectance) * base * irradiance(n) / kPi;
  return spec + diffuse;
}

const PrefilteredIbl& IblCache::get(const Environment& environment) {
  if (ibl_.empty() || ibl_.sourceHash() != environment.contentHash()) {
    ibl_ = PrefilteredIbl(environment, options_);
    ++builds_;
  }
  return ibl_;
}

}  // namespace holo::reflect
