#include "holo/reflect/prefiltered_ibl.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/reflect/dfg_table.hpp"
#include "holo/reflect/lobe_integral.hpp"

namespace holo::reflect {

namespace {

constexpr int kMinLevelSize = 48;

int floorPow2(int v) {
  int p = 1;
  while (p * 2 <= v) p *= 2;
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

}  // namespace

PrefilteredIbl::PrefilteredIbl(const Environment& env, PrefilterOptions options)
    : sh_(env),
      sun_(findPanoramaSun(env, options.sun)),
      proxy_(env.proxy()),
      source_hash_(env.contentHash()) {
  std::array<vec3, 9> sunless = sh_.coefficients();
  for (std::size_t i = 0; i < sunless.size(); ++i) sunless[i] -= sun_.radiance_sh[i];
  sunless_sh_ = IrradianceSH(sunless);
  const int levels = std::max(2, options.levels);
  int base = options.base_size;
  if (base <= 0) base = std::clamp(floorPow2(std::max(1, env.panorama().cols / 4)), 16, 1024);
  base = floorPow2(std::max(base, 4));

  levels_.resize(std::size_t(levels));
  // Level 0 is the mirror; levels 1.. are evenly spaced in sqrt(roughness) from min_roughness
  // to 1, which keeps the error of interpolating between neighbours about even (measured).
  const float s0 = std::sqrt(std::clamp(options.min_roughness, 0.01f, 1.0f));
  level_roughness_.assign(std::size_t(levels), 0.0f);
  for (int l = 1; l < levels; ++l) {
    const float s = levels == 2 ? 1.0f : s0 + (1.0f - s0) * float(l - 1) / float(levels - 2);
    level_roughness_[std::size_t(l)] = s * s;
  }
  if (env.panorama().empty()) {
    for (auto& level : levels_) level = OctahedralMap(16);
    return;
  }
  levels_[0] = resamplePanorama(env.panorama(), env.yaw(), base);
  LobeQuadratureOptions quadrature;
  quadrature.tail_ratio = options.tail_ratio;
  const GgxLobeIntegral integral(env.panorama(), env.yaw(), quadrature);
  const float density = float(std::max(1, options.texel_density));
  for (int l = 1; l < levels; ++l) {
    const float roughness = levelRoughness(l);
    const auto lobe = integral.lobe(roughnessToAlpha(roughness));
    // Texels about roughness / texel_density * 3.5 radians wide keep bilinear lookups within
    // ~1% of the lobe integral; rough levels keep kMinLevelSize so that a sun's wide lobe is
    // still resolved (measured, docs/reflect.md).
    const int size = std::clamp(int(std::ceil(density / roughness)), kMinLevelSize, 2 * base);
    OctahedralMap& out = levels_[std::size_t(l)];
    out = OctahedralMap(size);
    tbb::parallel_for(tbb::blocked_range<int>(0, size), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < size; ++x) out.at(x, y) = integral.integrate(out.texelDirection(x, y), lobe);
    });
  }
  for (const OctahedralMap& level : levels_)
    for (int y = 0; y < level.size(); ++y)
      for (int x = 0; x < level.size(); ++x)
        if (isFinite(level.at(x, y))) brightest_ = glm::max(brightest_, level.at(x, y));
}

vec3 PrefilteredIbl::specular(const vec3& direction, float roughness) const {
  if (levels_.empty()) return vec3(0.0f);
  const float r = std::clamp(roughness, 0.0f, 1.0f);
  // Find the two levels around r and blend linearly in GGX alpha (= r^2), which follows the
  // lobe's width better than r does (measured).
  int l1 = 1;
  while (l1 < levelCount() - 1 && level_roughness_[std::size_t(l1)] < r) ++l1;
  const float r0 = level_roughness_[std::size_t(l1 - 1)], r1 = level_roughness_[std::size_t(l1)];
  const float t = std::clamp((r * r - r0 * r0) / std::max(r1 * r1 - r0 * r0, 1e-12f), 0.0f, 1.0f);
  const vec2 uv = octahedralEncode(direction);
  const vec3 a = levels_[std::size_t(l1 - 1)].bilinearAt(uv);
  if (t <= 0.0f) return a;
  const vec3 b = levels_[std::size_t(l1)].bilinearAt(uv);
  return (1.0f - t) * a + t * b;
}

void PrefilteredIbl::setRelicTurn(const vec3& pivot, float angle_rad) {
  turn_angle_ = std::isfinite(angle_rad) ? angle_rad : 0.0f;
  turn_cos_ = std::cos(turn_angle_);
  turn_sin_ = std::sin(turn_angle_);
  turn_pivot_ = pivot;
}

SplitSumShading PrefilteredIbl::shadeParts(const SurfaceMaterial& m, const vec3& n, const vec3& wo,
                                           const vec3& reflected, const vec3& position,
                                           const vec3* irradiance_at) const {
  SplitSumShading parts;
  const float nv = glm::dot(n, wo);
  if (!(nv > 0.0f)) return parts;
  const float metallic = std::clamp(m.metallic, 0.0f, 1.0f);
  const float s = std::clamp(m.specular, 0.0f, 1.0f);
  const vec3 base = glm::clamp(m.base_colour, vec3(0.0f), vec3(1.0f));
  const vec2 ab = dfg(nv, m.roughness);
  const vec3 dielectric_f0 = dielectricF0(m.ior, m.specular_colour);
  const vec3 f0 = (1.0f - metallic) * dielectric_f0 * s + metallic * base;
  const float f90 = (1.0f - metallic) * s + metallic;
  parts.specular_scale = f0 * ab.x + f90 * ab.y;
  parts.environment = seenFrom(position, reflected, m.roughness);
  // The diffuse keeps what the strongest channel of the dielectric's reflection leaves
  // (KHR_materials_specular's fresnel_mix).
  const vec3 dielectric_reflectance = dielectric_f0 * s * ab.x + s * ab.y;
  parts.diffuse = (1.0f - metallic) * (1.0f - maxComponent(dielectric_reflectance)) * base *
                  (irradiance_at ? *irradiance_at : irradiance(n)) / kPi;
  return parts;
}

vec3 PrefilteredIbl::shade(const SurfaceMaterial& m, const vec3& n, const vec3& wo,
                           const vec3& position) const {
  const SplitSumShading parts = shadeParts(m, n, wo, glm::reflect(-wo, n), position);
  return parts.environment * parts.specular_scale + parts.diffuse;
}

const PrefilteredIbl& IblCache::get(const Environment& environment) {
  if (ibl_.empty() || ibl_.sourceHash() != environment.contentHash()) {
    ibl_ = PrefilteredIbl(environment, options_);
    ++builds_;
  }
  return ibl_;
}

}  // namespace holo::reflect
